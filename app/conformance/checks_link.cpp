// Handshake and the plain requests (PROTOCOL.md 7, 9.1): INFO, STATUS_GET,
// PING, and what the firmware does with frames that are not requests.
#include <fmt/format.h>

#include <optional>

#include "app/conformance/suite.hpp"

namespace nlsoft::console::conformance {

namespace {
using Clock = std::chrono::steady_clock;
}

void check_handshake(Suite& s, std::chrono::seconds patience) {
  const auto asked = Clock::now();
  const LinkStats before = s.pr.stats();
  Frame f;
  while (true) {
    try {
      f = s.pr.request(p::InfoGet{}, 1);
      break;
    } catch (const LinkError&) {
      // The console's own diagnosis: a silent line, noise, an echo.
      const auto waited = Clock::now() - asked;
      if (waited >= patience) throw LinkError(s.pr.no_info_words(before, waited));
    }
  }
  if (!as_info(f, s.info)) {
    s.check("handshake", false, "INFO_GET answered by " + describe(f));
    throw LinkError("no usable INFO: cannot go on");
  }
  const p::Info& i = s.info.info;
  std::vector<std::string> bad;
  if (i.protocol_version != p::kProtocolVersion) bad.push_back(fmt::format("protocol_version {}", i.protocol_version));
  if (i.n < 1 || i.n > p::kMaxTelemetryDim) bad.push_back(fmt::format("n {}", i.n));
  if (i.m < 1 || i.m > p::kMaxTelemetryDim) bad.push_back(fmt::format("m {}", i.m));
  if (i.max_n < 1 || i.max_nc < 1 || i.max_nc > i.max_n) bad.push_back(fmt::format("max_n {} max_nc {}", i.max_n, i.max_nc));
  if (i.loop_rate_hz == 0) bad.push_back("loop_rate_hz 0");
  if (i.platform > 2 && i.platform != 255) bad.push_back(fmt::format("platform {}", i.platform));
  const std::string what = fmt::format("{} {}.{}.{}, protocol {}.{}, platform {}, n={} m={} max_n={} max_nc={}, {} Hz",
                                       i.firmware, i.fw_major, i.fw_minor, i.fw_patch, i.protocol_version,
                                       s.info.protocol_minor, i.platform, i.n, i.m, i.max_n, i.max_nc, i.loop_rate_hz);
  s.check("handshake", bad.empty(), bad.empty() ? what : "implausible " + join(bad, ", ") + " (" + what + ")");
  if (i.protocol_version != p::kProtocolVersion) throw LinkError("firmware speaks another protocol version");

  // Protocol 1.1: INFO_EX with the transfer limits of the kinds it offers.
  std::vector<std::string> lim;
  if (f.type != uint8_t(p::MsgType::InfoEx)) lim.push_back(fmt::format("INFO_GET answered by {} (protocol 1.0)", p::message_name(f.type)));
  if (s.info.protocol_minor < 1) lim.push_back(fmt::format("protocol_minor {}", s.info.protocol_minor));
  if ((i.capabilities & p::capability::kXferRefTable) && s.info.table_max < 12) lim.push_back(fmt::format("table_max {}", s.info.table_max));
  if ((i.capabilities & p::capability::kXferModel) && s.info.model_max < 32) lim.push_back(fmt::format("model_max {}", s.info.model_max));
  s.check("info_ex", lim.empty(),
          lim.empty() ? fmt::format("INFO_EX: table_max {} B, model_max {} B", s.info.table_max, s.info.model_max)
                      : join(lim, "; "));
}

void check_basics(Suite& s) {
  s.group("basics");
  const Frame f = s.pr.request(p::StatusGet{});
  p::Status st;
  if (as(f, st)) {
    std::string note;
    if (st.run_state != uint8_t(p::RunState::Idle)) {
      // A run left active would make some refusals differ.
      const Frame stop = s.pr.request(p::RunStop{});
      note = fmt::format("; run {} was active (state {}), stopped it: {}", st.run_id, st.run_state, describe(stop));
    }
    s.telemetry_mask = st.telemetry_mask;
    s.check("status_get", true,
            fmt::format("STATUS uptime {} ms, run_state {}, frames_in {}{}", st.uptime_ms, st.run_state, st.frames_in, note));
  } else {
    s.check("status_get", false, "STATUS_GET answered by " + describe(f));
  }

  p::Ping ping;
  ping.nonce = s.random();
  const Frame g = s.pr.request(ping);
  p::Pong pong;
  if (!as(g, pong))
    s.check("ping", false, "PING answered by " + describe(g));
  else
    s.check("ping", pong.nonce == ping.nonce,
            fmt::format("nonce 0x{:08x} sent, 0x{:08x} echoed, uptime {} ms", ping.nonce, pong.nonce, pong.uptime_ms));

  // A firmware-to-console type sent to the firmware: a known type, so it
  // decodes, and NACK unsupported with no field to blame.
  {
    p::Ack ack;
    ack.request_type = uint8_t(p::MsgType::Ping);
    const uint8_t seq = s.pr.next_seq();
    // Up to 4 copies, as a request is retried: a copy is answered from the
    // stored reply, and no answer at all is this check's failure, not a link error.
    std::optional<Frame> r;
    for (int copy = 0; copy < 4 && !r; ++copy)
      r = s.pr.try_exchange(uint8_t(p::MsgType::Ack), seq, Probe::wire(ack, seq), s.pr.timeout());
    s.check("reply_type_refused", r && nacked(*r, p::StatusCode::Unsupported, p::kNoField, p::kNoField),
            "an ACK frame sent as a request: " + (r ? describe(*r) : std::string("no reply")));
  }
  // A request with the REPLY flag is no request: ignored, no reply.
  {
    p::Ping bogus;
    bogus.nonce = s.random();
    const uint8_t seq = s.pr.next_seq();
    p::Ping fence;
    fence.nonce = s.random();
    Frame fence_answer;
    const auto heard = s.pr.send_fenced(Probe::wire(bogus, seq, p::frame_flags::kReply), fence, fence_answer);
    s.check("reply_flag_ignored", heard.empty(),
            heard.empty() ? "PING with REPLY set: no reply"
                          : fmt::format("PING with REPLY set answered by {}", describe(heard.front())));
  }
}

}  // namespace nlsoft::console::conformance
