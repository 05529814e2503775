#pragma once
// A test that records runs by scripted sessions on nlsoft-firmware-sim
// (--sim-fast) into a database of its own, then runs console commands on
// them. The including test program defines NLSOFT_CONSOLE_BIN and
// NLSOFT_FIRMWARE_SIM_BIN.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <fstream>
#include <string>

#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::test {

class SimSessionTest : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1); }
  ProcessResult console(const std::string& args) const {
    return run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + args);
  }
  std::string db() const { return dir_.file("runs.db"); }
  // A session on the simulator running `script`; its runs recorded in db().
  void session(const std::string& rig, const std::string& script) {
    const std::string file = dir_.file("s.nls");
    std::ofstream(file) << script;
    const auto r = console("--sim " + rig + " --sim-fast --db " + shell_quote(db()) + " --script " + shell_quote(file));
    ASSERT_EQ(r.code, 0) << r.output;
  }
  TempDir dir_;
};

}  // namespace nlsoft::test
