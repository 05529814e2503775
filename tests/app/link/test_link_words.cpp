// What the console says when a port gives no firmware, run as a user runs
// it: the real nlsoft-console against a pty whose far end is silent or
// echoes. The handshake's failure names one wait (how long it asked) and
// what the line did; `conformance` says the same, in the same words.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <fstream>
#include <regex>
#include <string>

#include "app/support/fake_peer.hpp"
#include "protocol/encoder.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {
namespace {

namespace p = nlsoft::protocol;
using test::FakePeer;
using test::run_process;
using test::shell_quote;

// Every duration the text gives: "10.3 s", "250 ms".
std::vector<std::string> durations(const std::string& text) {
  std::vector<std::string> out;
  const std::regex d(R"((\d+(\.\d+)?) ?(ms|s)\b)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), d); it != std::sregex_iterator(); ++it)
    out.push_back(it->str());
  return out;
}

TEST(LinkWords, ASilentPortFailsTheHandshakeWithOneWaitAndWhatArrived) {
  FakePeer peer([](FakePeer&, const p::FrameView&) {});
  test::TempDir dir;
  const std::string script = dir.file("s.nls");
  std::ofstream(script) << "get Lambda\n";
  const auto r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + shell_quote(peer.path()) + " --no-record --script " +
                             shell_quote(script));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("no INFO in "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("of asking: nothing arrived from " + peer.path() +
                          ": is the firmware running, at 115200 baud?"),
            std::string::npos)
      << r.output;
  // One wait in the error: how long it asked, at least the 10 s a board gets.
  const size_t at = r.output.find("error: ");
  ASSERT_NE(at, std::string::npos) << r.output;
  const std::string error = r.output.substr(at, r.output.find('\n', at) - at);
  const auto waits = durations(error);
  ASSERT_EQ(waits.size(), 1u) << error;
  EXPECT_GE(std::stod(waits[0]), 10.0) << error;
}

// A line that gives back what is written: the conformance suite tells it
// from a silent one, as the console does, and stops with a link error.
TEST(LinkWords, ConformanceNamesAnEchoingLineAsTheConsoleDoes) {
  FakePeer peer([](FakePeer& pe, const p::FrameView& f) {
    uint8_t wire[p::kWireBufferSize];
    const size_t n = p::encode_frame(f.header.type, f.header.seq, f.header.flags, f.payload, f.header.length, wire,
                                     sizeof wire);
    pe.write(wire, n);
  });
  const auto r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " conformance " + shell_quote(peer.path()));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("of asking: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("the console's own frames came back from " + peer.path() + " ("),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("and nothing else: the line echoes what is sent"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("no INFO for 10 s"), std::string::npos) << r.output;
}

// The horizons: PARAM_DESC says 255 for every build, the simulated hasel
// build holds 128 (INFO max_n). The console advertises the real range, so
// `tune` refuses a range past it up front, and a `set` past it says the limit.
TEST(LinkWords, AHorizonPastTheBuildsCapacityIsRefusedWithTheLimit) {
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  test::TempDir dir;
  const std::string script = dir.file("n.nls");
  std::ofstream(script) << "set N 255\n";
  auto r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --no-record --script " + shell_quote(script));
  EXPECT_EQ(r.code, 2) << r.output;
  // The whole script is checked against the advertised range before it runs.
  EXPECT_NE(r.output.find("n.nls:1: N = 255 is out of range [1, 128]"),
            std::string::npos)
      << r.output;
  r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " tune --sim hasel --sim-fast --no-record --param N=1..255 --budget 2");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("outside N's range [1, 128]"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace nlsoft::console
