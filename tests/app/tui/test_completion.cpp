// Tab at the `:` line completes commands, parameter names, options,
// plot signals and reference kinds; an ambiguous word lists its choices.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "app/tui/completion.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console::tui {
namespace {

const std::vector<std::string> kParams = {"Q", "Lambda", "s", "b", "r", "N", "N1", "Nc", "mode", "feedback", "safe_state"};

TEST(Completion, CommandsParametersOptionsSignals) {
  EXPECT_EQ(complete_command("swe", kParams).text, "sweep ");
  EXPECT_EQ(complete_command("set Lam", kParams).text, "set Lambda ");
  EXPECT_EQ(complete_command("get saf", kParams).text, "get safe_state ");
  EXPECT_EQ(complete_command("set mode f", kParams).text, "set mode fd ");
  EXPECT_EQ(complete_command("set safe_state n", kParams).text, "set safe_state neutral ");
  EXPECT_EQ(complete_command("plot co", kParams).text, "plot co");  // cost or compute
  EXPECT_EQ(complete_command("plot co", kParams).candidates, (std::vector<std::string>{"cost", "compute"}));
  EXPECT_EQ(complete_command("ref sw", kParams).text, "ref swirl ");
  EXPECT_EQ(complete_command("ident pr", kParams).text, "ident prbs ");
  EXPECT_EQ(complete_command("ident prbs 30s se", kParams).text, "ident prbs 30s seed=");  // no blank after '='
  EXPECT_EQ(complete_command("ident prbs 30s y_", kParams).candidates,
            (std::vector<std::string>{"y_from=", "y_offset="}));
}

TEST(Completion, AmbiguousWordsExtendToWhatTheyShareAndListTheChoices) {
  const Completion c = complete_command("s", kParams);
  EXPECT_EQ(c.text, "s");
  EXPECT_EQ(c.candidates, (std::vector<std::string>{"set", "start", "stop", "settings", "sweep"}));
  EXPECT_EQ(complete_command("sett", kParams).text, "settings ");
  EXPECT_EQ(complete_command("settings d", kParams).text, "settings defaults ");
  const Completion n = complete_command("set N", kParams);
  EXPECT_EQ(n.text, "set N");
  EXPECT_EQ(n.candidates, (std::vector<std::string>{"N", "N1", "Nc"}));
  const Completion none = complete_command("set zz", kParams);
  EXPECT_EQ(none.text, "set zz");
  EXPECT_TRUE(none.candidates.empty());
  EXPECT_EQ(complete_command("run 10s ", kParams).text, "run 10s ");  // nothing to offer
}

// File arguments complete from the folder the word names, as in a shell:
// a folder ends in '/' and takes no blank, so Tab goes on into it.
TEST(Completion, FileArgumentsCompleteFromTheFolderTheyName) {
  test::TempDir dir;
  std::ofstream(dir.file("hasel-v2.nlsm")) << "x";
  std::ofstream(dir.file("hasel-v3.nlsm")) << "x";
  std::ofstream(dir.file(".hidden.nlsm")) << "x";
  std::filesystem::create_directory(dir.file("runs"));
  const std::string d = dir.path + "/";
  const Completion two = complete_command("model upload " + d + "h", kParams);
  EXPECT_EQ(two.text, "model upload " + d + "hasel-v");
  EXPECT_EQ(two.candidates, (std::vector<std::string>{d + "hasel-v2.nlsm", d + "hasel-v3.nlsm"}));
  EXPECT_EQ(complete_command("model upload " + d + "hasel-v3", kParams).text, "model upload " + d + "hasel-v3.nlsm ");
  EXPECT_EQ(complete_command("params save " + d + "r", kParams).text, "params save " + d + "runs/");
  EXPECT_EQ(complete_command("ref load " + d + ".h", kParams).text, "ref load " + d + ".hidden.nlsm ");
  EXPECT_EQ(complete_command("mod", kParams).text, "model ");
  EXPECT_EQ(complete_command("model up", kParams).text, "model upload ");
}

}  // namespace
}  // namespace nlsoft::console::tui
