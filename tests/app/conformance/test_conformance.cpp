// `nlsoft-console conformance --sim PLATFORM`: the protocol conformance
// suite against nlsoft-firmware-sim passes every check.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "app/support/run_process.hpp"
#include "support/text_checks.hpp"

namespace nlsoft::console {
namespace {

class Conformance : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1); }
};

// Every platform's simulator passes every check, and the checks the
// protocol's rules need are among them.
TEST_F(Conformance, SimulatorPassesEveryCheckOnEveryPlatform) {
  for (const char* platform : {"msd", "hasel", "tendon"}) {
    SCOPED_TRACE(platform);
    const auto r = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance --sim " + platform);
    EXPECT_EQ(r.code, 0) << r.output;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"((\d+) passed, 0 failed)"))) << r.output;
    EXPECT_GE(std::stoi(m[1]), 75) << r.output;
    // Protocol 1.2: the simulator names the rig file it serves, with that
    // file's hash, and refuses a too wide model at its header.
    EXPECT_NE(r.output.find(std::string("PASS rig_info: rig ") + platform + ", hash "), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find(std::string("PASS rig_info: rig ") + platform + ", hash 00000000"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("refused at the first XFER_CHUNK (unsupported, field 2)"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("FAIL "), std::string::npos) << r.output;
    for (const char* name :
         {"PASS handshake:", "PASS info_ex:", "PASS param_hash:", "PASS reply_type_refused:", "PASS reply_flag_ignored:",
          "PASS param_set_inconsistent:", "PASS param_set_too_large:", "PASS ref_refused pringle center[2]=Inf:",
          "PASS ref_unused_ignored:", "PASS duplicate_request:", "PASS reused_seq_executed:", "PASS replayed_seq:",
          "PASS pipelined:", "PASS byte_at_a_time:", "PASS bit_flips:", "PASS garbage_burst:", "PASS bad_crc:",
          "PASS unknown_type:", "PASS telemetry_accounting:", "PASS watchdog_trips:", "PASS watchdog_resume:",
          "PASS xfer_heal:", "PASS xfer_resume:", "PASS xfer_begin_too_large:", "PASS xfer_bad_checksum:",
          "PASS params_restored:", "PASS every_message:", "PASS reply_seq:", "PASS rig_info:", "PASS rig_name:",
          "PASS rig_hash_stable:", "PASS rig_shapes:", "PASS xfer_model_shape_refused:",
          "PASS xfer_model_header_split:", "PASS xfer_model_too_many_layers:",
          // Protocol 1.3: identification runs.
          "PASS ident_refusals:", "PASS ident_starts:", "PASS ident_inputs_in_limits:", "PASS ident_retry:",
          "PASS ident_stops_on_hold_and_stop:", "PASS ident_ends_after_duration:", "PASS ident_watchdog:",
          "PASS ident_run_start_refused:"})
      EXPECT_NE(r.output.find(name), std::string::npos) << name << "\n" << r.output;
  }
}

// With --shape-list the simulator serves RIG_INFO accept 0, as an MCU
// image: the suite then sees a model of a size no listed shape has refused
// at XFER_BEGIN, before any byte of it, and everything else passes as well.
TEST_F(Conformance, ASimulatorServingAShapeListRefusesAModelAtBeginByItsSize) {
  const auto r = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance --sim msd --shape-list");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("PASS rig_shapes: 1 listed shape, each ending in n=1 units"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("a size no listed shape has): refused at XFER_BEGIN (unsupported, field 2)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("PASS xfer_model_header_split:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("PASS xfer_model_too_many_layers:"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("FAIL "), std::string::npos) << r.output;
  // Only the simulator can be told what to list.
  const auto port = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance /dev/null --shape-list");
  EXPECT_EQ(port.code, 2) << port.output;
  EXPECT_NE(port.output.find("--shape-list makes the simulator list its shapes; give --sim too"), std::string::npos)
      << port.output;
}

TEST_F(Conformance, JsonReportsEveryCheck) {
  const auto r = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance --sim hasel --json");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("\"failed\":0,\"link_error\":null}"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"target\":\"sim hasel\""), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(
                "{\"group\":\"params\",\"name\":\"param_set_out_of_range\",\"pass\":true,\"detail\":"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("PASS "), std::string::npos) << "text lines in the JSON output\n" << r.output;
}

// A rig file of the user's, not one of the shipped rigs: tendon's rig under
// another name and tuning is served by the simulator and passes; a file
// with no plant is refused before a simulator starts.
TEST_F(Conformance, AnyRigFileWithAPlantIsServedAndPasses) {
  const std::string dir = ::testing::TempDir() + "conformance-any-rig";
  std::filesystem::create_directories(dir);
  std::string rig = std::regex_replace(nlsoft::test::slurp(NLSOFT_SOURCE_DIR "/rigs/tendon.toml"), std::regex("name = \"tendon\""), "name = \"bender\"",
                                       std::regex_constants::format_first_only);
  rig = std::regex_replace(rig, std::regex("\nQ = \\[[^\n]*"), "\nQ = [1e-3, 4e3, 3e3]");
  ASSERT_NE(rig.find("name = \"bender\""), std::string::npos);
  ASSERT_NE(rig.find("Q = [1e-3, 4e3, 3e3]"), std::string::npos);
  std::ofstream(dir + "/bender.toml") << rig;
  auto r = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance --sim " + dir + "/bender.toml --json");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("\"target\":\"sim bender\""), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"failed\":0,\"link_error\":null}"), std::string::npos) << r.output;
  // The simulator serves the file's own rig: its name on the wire.
  EXPECT_NE(r.output.find("rig bender, hash "), std::string::npos) << r.output;

  std::ofstream(dir + "/bare.toml") << std::regex_replace(rig, std::regex("\\[plant\\]\nkind = \"tendon\"\n"), "");
  r = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance --sim " + dir + "/bare.toml");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--sim: rig 'bender' (" + dir + "/bare.toml) has no [plant]: nothing simulates it"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("passed"), std::string::npos) << r.output;
}

TEST_F(Conformance, QemuWithoutItsImageIsAClearError) {
  ::setenv("NLSOFT_M4_IMAGE", "/nonexistent/nlsoft-m4-msd-hil.elf", 1);
  const auto r = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance --qemu msd");
  ::unsetenv("NLSOFT_M4_IMAGE");
  EXPECT_NE(r.code, 0) << r.output;
  EXPECT_EQ(r.output.find("passed"), std::string::npos) << r.output;
}

TEST_F(Conformance, ABoardWithoutQemuOrAnUnknownBoardIsAUsageError) {
  auto r = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance /dev/null --board stm32f4");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("give --qemu too"), std::string::npos) << r.output;
  r = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance --qemu hasel --board nucleo");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_EQ(r.output.find("passed"), std::string::npos) << r.output;
}

TEST_F(Conformance, NoPortIsAUsageError) {
  const auto r = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance");
  EXPECT_EQ(r.code, 2) << r.output;
}

}  // namespace
}  // namespace nlsoft::console
