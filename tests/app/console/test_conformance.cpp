// `nlsoft-console conformance --sim PLATFORM`: the protocol conformance
// suite against nlsoft-firmware-sim passes every check.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <regex>

#include "run_process.hpp"

namespace nlsoft::console {
namespace {

class Conformance : public ::testing::Test {
 protected:
  void SetUp() override { ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1); }
};

TEST_F(Conformance, SimulatorPassesEveryCheck) {
  const auto r = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance --sim msd");
  EXPECT_EQ(r.code, 0) << r.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.output, m, std::regex(R"((\d+) passed, 0 failed)"))) << r.output;
  EXPECT_GE(std::stoi(m[1]), 15) << r.output;
  EXPECT_EQ(r.output.find("FAIL "), std::string::npos) << r.output;
  for (const char* name : {"PASS handshake:", "PASS duplicate_request:", "PASS bad_crc:", "PASS unknown_type:",
                           "PASS telemetry:", "PASS xfer_heal:", "PASS xfer_bad_checksum:", "PASS params_restored:"})
    EXPECT_NE(r.output.find(name), std::string::npos) << name << "\n" << r.output;
}

TEST_F(Conformance, JsonReportsEveryCheck) {
  const auto r = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance --sim hasel --json");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("\"failed\":0,\"link_error\":null}"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"name\":\"param_set_out_of_range\",\"pass\":true"), std::string::npos) << r.output;
}

TEST_F(Conformance, NoPortIsAUsageError) {
  const auto r = test::run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance");
  EXPECT_EQ(r.code, 2) << r.output;
}

}  // namespace
}  // namespace nlsoft::console
