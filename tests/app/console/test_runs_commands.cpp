// The session around the runs: `runs list` with reference and nRMSE (and
// --json), `runs label`, `runs delete`, a reference sent mid-run recorded,
// and the CLI's contract (--version; usage errors exit 2).
#include <gtest/gtest.h>
#include <stdlib.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "app/record/recorder.hpp"
#include "app/record/run_store.hpp"
#include "app/record/sqlite.hpp"
#include "run_process.hpp"
#include "temp_dir.hpp"

namespace nlsoft::console {
namespace {

using test::run_process;
using test::shell_quote;

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

class RunsCommands : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1); }
  test::ProcessResult console(const std::string& args) const {
    return run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + args);
  }
  test::ProcessResult runs(const std::string& args) const { return console("runs " + args + " --db " + shell_quote(db())); }
  // Run 1 starts with no reference and gets Infinity during it; run 2 is a
  // Swirl from the start.
  void record() {
    const std::string script = dir_.file("s.nls");
    std::ofstream(script) << "start\nwait 500ms\nref infinity\nwait 500ms\nstop\nref swirl\nrun 1s label=swirl\n";
    const auto r = console("--sim hasel --db " + shell_quote(db()) + " --script " + shell_quote(script));
    ASSERT_EQ(r.code, 0) << r.output;
  }
  std::string db() const { return dir_.file("runs.db"); }
  test::TempDir dir_;
};

TEST_F(RunsCommands, ListShowsReferenceAndNrmseAndAMidRunReferenceIsRecorded) {
  record();
  auto r = runs("list");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "reference")) << r.output;
  EXPECT_TRUE(contains(r.output, "nrmse")) << r.output;
  EXPECT_TRUE(contains(r.output, "infinity")) << "the reference sent during run 1\n" << r.output;
  EXPECT_TRUE(contains(r.output, "swirl")) << r.output;

  r = runs("list --json");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output);
  ASSERT_TRUE(j.is_array());
  ASSERT_EQ(j.size(), 2u);
  EXPECT_EQ(j[0]["reference"]["kind"], "infinity");
  EXPECT_EQ(j[1]["reference"]["kind"], "swirl");
  EXPECT_EQ(j[1]["label"], "swirl");
  EXPECT_TRUE(j[0]["nrmse"].is_number()) << j.dump();

  // The change itself, with its time, in the run's log.
  r = runs("show 1");
  EXPECT_TRUE(contains(r.output, "reference = {")) << r.output;
  EXPECT_TRUE(contains(r.output, "\"kind\":\"infinity\"")) << r.output;
}

TEST_F(RunsCommands, LabelAndDeleteChangeOneRunWhole) {
  record();
  auto r = runs("label 2 " + shell_quote("Lambda 4, smoother"));
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(RunStore(db()).run(2).label, "Lambda 4, smoother");
  r = runs("delete 1");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "run 1 deleted")) << r.output;
  {
    RunStore store(db());
    const auto list = store.list();
    ASSERT_EQ(list.size(), 1u);
    EXPECT_EQ(list[0].id, 2);
    EXPECT_TRUE(store.params(1).empty());
    EXPECT_GT(store.series(2).rows(), 0u) << "the other run keeps its samples";
    Db raw(db(), Db::Access::ReadOnly);
    Stmt c = raw.prepare("SELECT count(*) FROM samples WHERE id < ?");
    c.bind(1, sample_key(2, 0));
    ASSERT_TRUE(c.step());
    EXPECT_EQ(c.int64(0), 0) << "the run's samples go with it";
  }
  r = runs("delete 9");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "no run 9")) << r.output;
  r = runs("label 9 x");
  EXPECT_EQ(r.code, 2) << r.output;
}

TEST_F(RunsCommands, AnUnfinishedRunIsDeletedOnlyWithForce) {
  int64_t id = 0;
  {
    Recorder rec(db());
    RunInfo ri;
    ri.platform = "hasel";
    ri.n = 3;
    ri.m = 6;
    id = rec.begin_run(ri);
    rec.flush();
  }
  auto r = runs("delete " + std::to_string(id));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "unfinished")) << r.output;
  EXPECT_EQ(RunStore(db()).list().size(), 1u) << "nothing deleted";
  r = runs("delete --force " + std::to_string(id));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(RunStore(db()).list().empty());
}

TEST(ConsoleCli, VersionAndUsageErrorsExitTwo) {
  auto r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " --version");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "nlsoft-console 0.1.0, wire protocol 1")) << r.output;
  for (const char* args : {"--no-such-option", "runs show", "runs show notanumber", "--sim nowhere",
                           "runs plot 1 2 3 --svg x.svg"}) {
    r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + args);
    EXPECT_EQ(r.code, 2) << args << ": " << r.output;
  }
}

}  // namespace
}  // namespace nlsoft::console
