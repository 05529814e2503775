// `params diff` and `params reset` against nlsoft-firmware-sim: the console's
// idea of the boot values must be the firmware's (a fresh firmware shows no
// difference on every platform), edits show up against their defaults, and
// a reset puts them back.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <string>
#include <vector>

#include "app/live/live_console.hpp"
#include "app/script/script_parser.hpp"
#include "app/support/sim_console.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {
namespace {

using test_support::connected_sim_console;

class ParamsDefaults : public ::testing::TestWithParam<const char*> {};

TEST_P(ParamsDefaults, AFreshFirmwareHoldsExactlyTheDefaultsTheConsoleKnows) {
  test::TempDir dir;
  auto c = connected_sim_console(GetParam(), dir);
  const std::vector<std::string> diff = c->params().diff_from_defaults();
  EXPECT_TRUE(diff.empty()) << diff.front();
}

INSTANTIATE_TEST_SUITE_P(EveryPlatform, ParamsDefaults, ::testing::Values("msd", "hasel", "tendon"));

TEST(ParamsDiffReset, EditsShowAgainstTheirDefaultsAndAResetPutsThemBack) {
  test::TempDir dir;
  auto c = connected_sim_console("hasel", dir);
  c->params().set("Lambda", {"0.5"});
  c->params().set("watchdog_ms", {"500"});
  c->params().set("mode", {"fd"});
  const std::vector<std::string> diff = c->params().diff_from_defaults();
  ASSERT_EQ(diff.size(), 3u);
  EXPECT_EQ(diff[0], "Lambda: 0.5 0.5 0.5 0.5 0.5 0.5 (default 1 1 1 1 1 1)");
  EXPECT_EQ(diff[1], "mode: 1 (fd) (default 0 (exact))");
  EXPECT_EQ(diff[2], "watchdog_ms: 500 (default 1000)");

  const std::vector<std::string> reset = c->params().reset_to_defaults();
  EXPECT_EQ(reset.size(), 3u);
  EXPECT_TRUE(c->params().diff_from_defaults().empty());
  EXPECT_EQ(c->params().get("Lambda").second, std::vector<double>(6, 1.0));
  EXPECT_EQ(c->params().get("watchdog_ms").second, std::vector<double>{1000});
  EXPECT_TRUE(c->params().reset_to_defaults().empty()) << "nothing left to send";
}

TEST(ParamsDiffReset, ScriptCommandsParseAndRefuseExtraWords) {
  EXPECT_EQ(parse_command("params diff", "t", 1).kind, Command::Kind::ParamsDiff);
  EXPECT_EQ(parse_command("params reset", "t", 1).kind, Command::Kind::ParamsReset);
  EXPECT_THROW(parse_command("params reset now", "t", 1), ScriptError);
  try {
    parse_command("params restore", "t", 3);
    FAIL() << "params restore parsed";
  } catch (const ScriptError& e) {
    EXPECT_NE(std::string(e.what()).find("expected save, load, reapply, diff or reset"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nlsoft::console
