#pragma once
// A LiveConsole connected to nlsoft-firmware-sim for `rig` (a shipped name or a file), recording
// into the test's own folder: what the in-process e2e tests start from.
#include <stdlib.h>

#include <memory>
#include <string>

#include "app/live/live_console.hpp"
#include "temp_dir.hpp"

namespace nlsoft::console::test_support {

inline std::unique_ptr<LiveConsole> connected_sim_console(const std::string& rig, const test::TempDir& dir) {
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  LiveOptions o;
  o.sim_rig = rig;
  o.db_path = dir.file("runs.db");
  auto c = std::make_unique<LiveConsole>(o);
  c->connect();
  return c;
}

}  // namespace nlsoft::console::test_support
