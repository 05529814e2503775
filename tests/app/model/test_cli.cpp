// The subcommands as a user runs them: the happy path end to end, and every
// bad input ends with a message, exit code 2 and no file written.
#include <gtest/gtest.h>

#include <regex>

#include <algorithm>
#include <fstream>

#include "app/model/model_store.hpp"
#include "cli_runner.hpp"
#include "support/text_checks.hpp"

using nlsoft::test::file_exists;
using nlsoft::test::run_cli;

namespace {

using nlsoft::test::slurp;

std::string cli_tmp(const std::string& name) { return ::testing::TempDir() + "/cli_" + name; }

}  // namespace

TEST(Cli, DatasetTrainInfoEval) {
  const std::string csv = cli_tmp("t.csv"), model = cli_tmp("t.nlsm");
  auto r = run_cli("dataset --rig tendon --out " + csv + " --steps 3000 --seed 4");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(slurp(csv).substr(0, 16), "time,u0,u1,y0,y1");
  r = run_cli("train --rig tendon --data " + csv + " --out " + model + " --epochs 2 --seed 3 --seeds 1 --lbfgs 50");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("test y2: MSE"), std::string::npos) << r.output;
  // Both streams into one pipe, as into a log file: the header comes first.
  ASSERT_NE(r.output.find("training on "), std::string::npos) << r.output;
  ASSERT_NE(r.output.find("one-step epoch 1/"), std::string::npos) << r.output;
  EXPECT_LT(r.output.find("training on "), r.output.find("one-step epoch 1/")) << r.output;

  // The file holds the candidate the choice table marks: the rig's GRU, or
  // the linear model where the GRU's short training left it behind.
  const size_t star = r.output.find("\n  * ");
  ASSERT_NE(star, std::string::npos) << r.output;
  const bool gru = r.output.compare(star + 5, 3, "GRU") == 0;  // after "\n  * "
  if (!gru) {
    EXPECT_NE(r.output.find("kept the linear model"), std::string::npos) << r.output;
  }
  // The kept row's one-step epochs are the summary's (rows once said 0).
  std::smatch row, summary;
  const std::string kept = r.output.substr(star, r.output.find('\n', star + 1) - star);
  if (std::regex_search(kept, row, std::regex(" after (\\d+) one-step epochs"))) {
    ASSERT_TRUE(std::regex_search(r.output, summary, std::regex("trained tendon model in [0-9.]+ s \\((\\d+) one-step epochs\\)")))
        << r.output;
    EXPECT_EQ(row[1].str(), summary[1].str()) << r.output;
    EXPECT_NE(row[1].str(), "0");
  }
  r = run_cli("model info " + model);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find(gru ? "GRU     21 -> 5" : "Dense   21 -> 3   linear"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("hash 0x"), std::string::npos);

  const std::string in = cli_tmp("x.csv"), out = cli_tmp("y.csv");
  std::ofstream(in) << std::string("0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0\n") +
                          "0.5,0.5,0.4,0.4,1,2,3,1,2,3,0.1,0.2,0.3,0.4,0.5,0.6,0.7,0.8,0.9,1,0.5\n";
  r = run_cli("model eval " + model + " --input " + in + " --output " + out);
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string y = slurp(out);
  EXPECT_EQ(std::count(y.begin(), y.end(), '\n'), 2);
  EXPECT_EQ(std::count(y.begin(), y.end(), ','), 4);
}

// `--platform`, the old spelling of --rig: still taken, said to be
// deprecated on stderr, and not both at once.
TEST(Cli, PlatformIsADeprecatedSpellingOfRig) {
  const std::string csv = cli_tmp("old.csv");
  auto r = run_cli("dataset --platform msd --out " + csv + " --steps 500");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("--platform is deprecated; say --rig msd"), std::string::npos) << r.output;
  EXPECT_EQ(slurp(csv).substr(0, 10), "time,u0,y0");
  r = run_cli("dataset --platform msd --rig msd --out " + cli_tmp("both.csv") + " --steps 500");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("excludes"), std::string::npos) << r.output;
}

TEST(Cli, BadInputExitsWithTwoAndWritesNothing) {
  const std::string csv = cli_tmp("ok.csv"), model = cli_tmp("ok.nlsm");
  ASSERT_EQ(run_cli("dataset --rig msd --out " + csv + " --steps 500").code, 0);
  ASSERT_EQ(run_cli("train --rig msd --data " + csv + " --out " + model).code, 0);
  const std::string good_model = slurp(model);

  const std::string bad_csv = cli_tmp("bad.csv");
  std::ofstream(bad_csv) << "time,u0,y0\n0,1,2\n0.001,oops,3\n";
  const std::string corrupt = cli_tmp("corrupt.nlsm");
  std::ofstream(corrupt) << good_model.substr(0, good_model.size() - 3) << "xyz";
  const std::string short_rows = cli_tmp("short.csv");
  std::ofstream(short_rows) << "1,2,3\n";

  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {"dataset --rig mars --out " + cli_tmp("n1.csv"), "unknown rig 'mars'"},
      {"dataset --rig msd", "--out is required"},
      {"dataset --rig msd --out " + cli_tmp("n1.csv") + " --steps 12x", "--steps must be an integer"},
      {"dataset --rig msd --out " + cli_tmp("n1.csv") + " --steps 5", "--steps"},
      {"train --rig msd --data " + cli_tmp("missing.csv") + " --out " + cli_tmp("n2.nlsm"), "cannot open"},
      {"train --rig msd --data " + bad_csv + " --out " + cli_tmp("n2.nlsm"), "not a number: 'oops'"},
      {"train --rig hasel --data " + csv + " --out " + cli_tmp("n2.nlsm"), "rig 'hasel' has m=6"},
      {"train --rig msd --data " + csv + " --out " + cli_tmp("n2.nlsm") + " --epochs -3", "--epochs"},
      {"train --rig msd --data " + csv + " --out " + cli_tmp("n2.nlsm") + " --lr abc", "--lr"},
      {"train --rig msd --data " + csv + " --out " + cli_tmp("n2.nlsm") + " --loss l1", "--loss"},
      {"train --rig msd --data " + csv + " --out " + cli_tmp("n2.nlsm") + " --arch lstm", "--arch"},
      {"model info " + corrupt, "not a valid model file"},
      {"model info " + cli_tmp("missing.nlsm"), "cannot open"},
      {"model eval " + model + " --input " + short_rows + " --output " + cli_tmp("n3.csv"), "the model takes p = 4"},
      {"model eval " + model + " --input " + bad_csv + " --output " + cli_tmp("n3.csv"), "not a number"},
      {"model import " + csv + " --out " + cli_tmp("n5.nlsm"), "not an HDF5 file"},
  };
  for (const Case& c : cases) {
    const auto r = run_cli(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
  }
  for (const char* f : {"n1.csv", "n2.nlsm", "n3.csv", "n5.nlsm"}) EXPECT_FALSE(file_exists(cli_tmp(f))) << f;

  // a failed run over an existing file leaves it as it was
  EXPECT_EQ(run_cli("train --rig msd --data " + bad_csv + " --out " + model).code, 2);
  EXPECT_EQ(slurp(model), good_model);
}

TEST(Cli, HelpTeaches) {
  const auto r = run_cli("train --help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.output.find("Example: nlsoft-console train"), std::string::npos) << r.output;
}
