// A command line's rig is read once, at the edge (app/target): `--sim
// hasel` and `--qemu hasel` resolve the name once and read the file once in
// the console, however many parts of it ask for the rig afterwards (the
// option's check, the image lookup, the simulator's settings file, the
// board's rig and its RIG_INFO check). The simulator, a process of its
// own, reads its own copy.
#include <CLI/CLI.hpp>
#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <fstream>
#include <vector>

#include "app/live/connect_args.hpp"
#include "app/live/live_console.hpp"
#include "app/target/target_args.hpp"
#include "app/support/temp_dir.hpp"
#include "host/files/cli_error.hpp"
#include "host/rig/rig.hpp"
#include "host/rig/rig_catalog.hpp"

namespace nlsoft::console {

using host::CliError;
using host::rig_args_resolved;
using host::rig_files_loaded;
using host::rig_path;

namespace {

struct Reads {
  long resolved, loaded;
  static Reads now() { return {rig_args_resolved(), rig_files_loaded()}; }
};

ConnectArgs parsed(std::vector<std::string> argv) {
  ConnectArgs a;
  CLI::App app;
  add_connect_options(app, a, "connect to");
  std::reverse(argv.begin(), argv.end());  // CLI11 takes them last first
  app.parse(argv);
  return a;
}

TEST(RigLoadedOnce, ASimConnectResolvesAndReadsTheRigOnce) {
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  test::TempDir dir;
  const Reads before = Reads::now();
  const ConnectArgs a = parsed({"--sim", "hasel", "--sim-fast", "--db", dir.file("runs.db")});
  LiveConsole console(live_options(a));
  console.connect();
  EXPECT_EQ(console.rig().name, "hasel");
  EXPECT_EQ(console.rig().file, rig_path("hasel"));  // (a resolution of the test's own, after the count)
  const Reads after = Reads::now();
  EXPECT_EQ(after.resolved - before.resolved, 1 + 1);
  EXPECT_EQ(after.loaded - before.loaded, 1);
}

TEST(RigLoadedOnce, AQemuTargetResolvesAndReadsTheRigOnce) {
  // The image QEMU would boot is not booted here: $NLSOFT_M4_IMAGE names
  // one, as a user's own build would.
  test::TempDir dir;
  const std::string image = dir.file("nlsoft-m4-hasel-hil.elf");
  std::ofstream(image) << "an image";
  ::setenv("NLSOFT_M4_IMAGE", image.c_str(), 1);
  const Reads before = Reads::now();
  const LiveOptions o = live_options(parsed({"--qemu", "hasel", "--db", dir.file("runs.db")}));
  ::unsetenv("NLSOFT_M4_IMAGE");
  const Reads after = Reads::now();
  ASSERT_NE(o.rig, nullptr);
  EXPECT_EQ(o.rig->name, "hasel");
  EXPECT_EQ(o.qemu_image, image);
  EXPECT_EQ(after.resolved - before.resolved, 1);
  EXPECT_EQ(after.loaded - before.loaded, 1);
}

// conformance resolves its target as the console does (app/target).
TEST(RigLoadedOnce, ConformancesTargetIsResolvedTheSameWay) {
  TargetArgs t;
  t.sim = "msd";
  const Reads before = Reads::now();
  const Target target = resolve_target(t, "", "");
  const Reads after = Reads::now();
  ASSERT_NE(target.rig, nullptr);
  EXPECT_EQ(target.rig->name, "msd");
  EXPECT_EQ(target.sim_rig, target.rig->file);
  EXPECT_TRUE(target.qemu_image.empty());
  EXPECT_EQ(after.resolved - before.resolved, 1);
  EXPECT_EQ(after.loaded - before.loaded, 1);
  t.board = "stm32f4";
  EXPECT_THROW(resolve_target(t, "", ""), CliError);  // --board without --qemu
}

TEST(RigLoadedOnce, ABadRigIsSaidInTheOptionsName) {
  try {
    live_options(parsed({"--sim", "no-such-rig"}));
    FAIL() << "a rig that is not there was taken";
  } catch (const CliError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("--sim: unknown rig 'no-such-rig'", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace nlsoft::console
