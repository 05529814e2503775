// The real nlsoft-console against a firmware that does what an honest one
// never would, on a pty: it connects like a small board (m = n = 1, w = 0,
// one parameter Lambda, 100 Hz), then sends the IDENT_SAMPLE of the report
// (m = 0, n = 58, w = 0) after the handshake, text full of escapes (its
// name, a unit, LOG), and runs whose telemetry carries NaN or whose step
// count goes back. The console must not crash, must say what it dropped,
// and must not pass a garbage run.
#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "app/support/fake_peer.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {
namespace {

namespace p = nlsoft::protocol;
using test::FakePeer;
using test::run_process;
using test::shell_quote;

struct Hostile {
  std::string name = "hostile";
  bool d1_after_handshake = false;  // the report's frame, at the first PARAM_GET
  bool log_escapes = false;         // a LOG line of escapes, likewise
  enum class Run { Honest, NanAtStep20, StepGoesBack } run = Run::Honest;
  std::atomic<int> param_sets{0};
};

void send_ack(FakePeer& pe, const p::FrameView& f) {
  p::Ack a;
  a.request_type = f.header.type;
  pe.reply(a, f.header.seq);
}

// The run's telemetry: y_true = y_ref = 0 (a perfect run but for what the
// mode makes of it), 60 frames for a run of 50 steps.
void send_run(FakePeer& pe, Hostile::Run mode) {
  p::Telemetry t;
  t.mask = p::telemetry_field::kStep | p::telemetry_field::kTime | p::telemetry_field::kYRef |
           p::telemetry_field::kYTrue | p::telemetry_field::kU;
  t.n = 1;
  t.m = 1;
  for (uint16_t i = 0; i < 60; ++i) {
    t.tseq = i;
    t.step = mode == Hostile::Run::StepGoesBack ? (i < 30 ? 1000u + i : uint32_t(i - 30)) : i;
    t.time_us = uint32_t(i) * 10000u;
    t.y_true[0] = mode == Hostile::Run::NanAtStep20 && i == 20 ? std::numeric_limits<float>::quiet_NaN() : 0.f;
    pe.send_unsolicited(t);
  }
}

FakePeer::Handler firmware(Hostile& h) {
  return [&h](FakePeer& pe, const p::FrameView& f) {
    switch (p::MsgType(f.header.type)) {
      case p::MsgType::InfoGet: {
        p::Info info;
        info.platform = uint8_t(p::Platform::Msd);
        info.m = 1;
        info.n = 1;
        info.max_n = 10;
        info.max_nc = 5;
        info.loop_rate_hz = 100;
        info.capabilities = p::capability::kParams | p::capability::kTelemetry | p::capability::kYTrue |
                            p::capability::kLog | p::capability::kIdent;
        std::snprintf(info.firmware, sizeof info.firmware, "%s", h.name.c_str());
        return pe.reply(info, f.header.seq);
      }
      case p::MsgType::ParamList: {
        p::ParamDesc d;
        d.count = 1;
        d.id = 1;
        d.type = uint8_t(p::ParamType::F32);
        d.size = 1;
        d.min = 0;
        d.max = 1e12f;
        std::snprintf(d.unit, sizeof d.unit, "%s", "\x1b[2J");
        std::snprintf(d.name, sizeof d.name, "%s", "Lambda");
        return pe.reply(d, f.header.seq);
      }
      case p::MsgType::ParamGet:
      case p::MsgType::ParamSet: {
        if (f.header.type == uint8_t(p::MsgType::ParamSet)) ++h.param_sets;
        p::ParamValue v;
        v.id = 1;
        v.type = uint8_t(p::ParamType::F32);
        v.count = 1;
        v.set_f32(0, 0.5f);
        pe.reply(v, f.header.seq);
        if (h.d1_after_handshake) {
          p::IdentSample s;
          s.m = 0;
          s.n = 58;
          s.w = 0;
          for (float& y : s.y) y = 1e30f;
          pe.send_unsolicited(s);
        }
        if (h.log_escapes) {
          p::Log l;
          l.level = 2;
          std::snprintf(l.text, sizeof l.text, "%s",
                        "\x1b]52;c;ZXZpbA==\x07\x1b[2J\x1b]0;owned\x07\x1b[1;1H\xc2\x9b" "31m\x9b" "32m\xe2\x80\xae"
                        "\nerror: fake console line");
          pe.send_unsolicited(l);
        }
        return;
      }
      case p::MsgType::StatusGet: {
        p::Status s;
        s.uptime_ms = 1000;
        s.tick_rate_hz = 1000000;
        return pe.reply(s, f.header.seq);
      }
      case p::MsgType::RunStart:
        send_ack(pe, f);
        return send_run(pe, h.run);
      case p::MsgType::Ping: {
        p::Ping ping;
        if (p::unpack(f, ping) != p::StatusCode::Ok) return;
        p::Pong pong;
        pong.nonce = ping.nonce;
        return pe.reply(pong, f.header.seq);
      }
      default: return send_ack(pe, f);
    }
  };
}

test::ProcessResult console(const FakePeer& peer, test::TempDir& dir, const std::string& script) {
  std::ofstream(dir.file("s.nls")) << script;
  return run_process(std::string(NLSOFT_CONSOLE_BIN) + " " + shell_quote(peer.path()) + " --db " +
                     shell_quote(dir.file("runs.db")) + " --script " + shell_quote(dir.file("s.nls")));
}

bool has_control(const std::string& s) {
  for (unsigned char c : s)
    if ((c < 0x20 && c != '\n') || c == 0x7f || c == 0x9b) return true;
  return false;
}

// The report's frame: 245 bytes the protocol's length rule accepts, 15
// floats past a Sample in the console that took it.
TEST(HostileFirmware, TheIdentSampleOfTheReportIsDroppedAndSaidNotACrash) {
  Hostile h;
  h.d1_after_handshake = true;
  FakePeer peer(firmware(h));
  test::TempDir dir;
  const auto r = console(peer, dir, "get Lambda\nwait 500ms\nget Lambda\necho still here\n");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("still here"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("dropped an IDENT_SAMPLE frame with m=0 n=58 w=0, the firmware's INFO says m=1 n=1 w=0"),
            std::string::npos)
      << r.output;
  const size_t first = r.output.find("dropped an IDENT_SAMPLE");
  EXPECT_EQ(r.output.find("dropped an IDENT_SAMPLE", first + 1), std::string::npos) << "said once: " << r.output;
}

// LOG text, the firmware's name and a unit reach standard error and the
// session log escaped: no clipboard write, screen clear, title or fake line.
TEST(HostileFirmware, ItsTextReachesTheTerminalAndTheSessionLogEscaped) {
  Hostile h;
  h.name = "fw\x1b]0;t\x07\nok";
  h.log_escapes = true;
  FakePeer peer(firmware(h));
  test::TempDir dir;
  const auto r = console(peer, dir, "get Lambda\nwait 500ms\n");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_FALSE(has_control(r.output)) << r.output;
  EXPECT_NE(r.output.find("\\x1b]52;c;ZXZpbA==\\x07\\x1b[2J"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\\u009b31m\\x9b32m\\u202e\\nerror: fake console line"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Lambda = 0.5 \\x1b[2J"), std::string::npos) << "the unit, escaped: " << r.output;
  EXPECT_EQ(r.output.find("\nerror: fake console line"), std::string::npos) << r.output;
}

// A firmware name with newlines plants no line in a parameter file, and a
// file naming a parameter twice is refused at its line, nothing applied.
TEST(HostileFirmware, AParameterFileHoldsOnlyWhatWasMeasured) {
  Hostile h;
  h.name = "x\nLambda 1e11\nQ 0";
  FakePeer peer(firmware(h));
  test::TempDir dir;
  auto r = console(peer, dir, "params save " + dir.file("p.txt") + "\n");
  ASSERT_EQ(r.code, 0) << r.output;
  std::ifstream in(dir.file("p.txt"));
  std::vector<std::string> values;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') values.push_back(line);
  ASSERT_EQ(values.size(), 1u) << "one line per parameter";
  EXPECT_EQ(values[0], "Lambda 0.5");

  std::ofstream(dir.file("twice.txt")) << "Lambda 2\nlambda 3\n";
  r = console(peer, dir, "params load " + dir.file("twice.txt") + "\n");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find(dir.file("twice.txt") + ":2: Lambda is named a second time (first at line 1)"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(h.param_sets.load(), 0) << "nothing applied";
}

// TELEMETRY with a NaN is counted lost, never scored: an expect on the run
// fails unless the script says lost=ok.
TEST(HostileFirmware, ARunWithNanTelemetryDoesNotPassAnExpect) {
  Hostile h;
  h.run = Hostile::Run::NanAtStep20;
  FakePeer peer(firmware(h));
  test::TempDir dir;
  const auto r = console(peer, dir, "run 500ms\nexpect max_error < 0.1\nexpect max_error < 0.1 lost=ok\n");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("dropped a TELEMETRY frame (step 20) carrying NaN or infinity"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("s.nls:2: expect max_error < 0.1 failed: run 1 lost 1 sample"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("ok: max_error = 0 < 0.1"), std::string::npos) << r.output;
}

// A step count that jumps back ends the run early, in words; it is not a
// completed run of 52 samples.
TEST(HostileFirmware, AStepCountThatGoesBackEndsTheRunEarly) {
  Hostile h;
  h.run = Hostile::Run::StepGoesBack;
  FakePeer peer(firmware(h));
  test::TempDir dir;
  const auto r = console(peer, dir, "run 500ms\n");
  EXPECT_EQ(r.code, 1) << r.output;
  EXPECT_NE(r.output.find("the firmware's step count went back from 1029 to 0"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("lost 0\n"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace nlsoft::console
