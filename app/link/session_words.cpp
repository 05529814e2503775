#include "app/link/session_words.hpp"

#include <fmt/format.h>

#include <cstring>

#include "app/link/protocol_version.hpp"
#include "protocol/catalog.hpp"
#include "host/rig/rig_catalog.hpp"

namespace nlsoft::console {

using host::rig_name_of_platform;

namespace p = nlsoft::protocol;

namespace {

}  // namespace

std::string platform_words(uint8_t platform) {
  const std::string shipped = rig_name_of_platform(platform);
  if (!shipped.empty()) return shipped;
  return platform == uint8_t(p::Platform::Custom) ? "custom" : fmt::format("#{}", platform);
}

namespace {

std::string firmware_words(const p::Info& i) {
  return fmt::format("{} {}.{}.{}", std::string(i.firmware, strnlen(i.firmware, sizeof i.firmware)), i.fw_major,
                     i.fw_minor, i.fw_patch);
}

std::string dimension_words(const p::Info& i) {
  return fmt::format("m={} n={} w={} nd={} dd={} max_n={} max_nc={}", i.m, i.n, i.w, i.nd, i.dd, i.max_n, i.max_nc);
}

}  // namespace

std::string identity_change(const p::Info& was, const p::Info& now) {
  std::vector<std::string> diffs;
  if (now.platform != was.platform)
    diffs.push_back(fmt::format("platform {} (was {})", platform_words(now.platform), platform_words(was.platform)));
  if (firmware_words(now) != firmware_words(was))
    diffs.push_back(fmt::format("firmware {} (was {})", firmware_words(now), firmware_words(was)));
  if (dimension_words(now) != dimension_words(was))
    diffs.push_back(fmt::format("dimensions {} (was {})", dimension_words(now), dimension_words(was)));
  std::string out;
  for (const std::string& d : diffs) out += (out.empty() ? "" : "; ") + d;
  return out;
}

std::string not_info_words(uint8_t reply_type) {
  return fmt::format("it answers INFO_GET with {}", p::message_name(reply_type));
}

std::string foreign_words(const std::string& port, const std::string& change) {
  return fmt::format("a different device now answers at {}: {}", port, change);
}

std::string wait_words(std::chrono::steady_clock::duration d) {
  const double ms = std::chrono::duration<double, std::milli>(d).count();
  // Whole milliseconds, truncated: a wait never reads longer than it was.
  return ms < 10000 ? fmt::format("{} ms", int64_t(ms)) : fmt::format("{:.1f} s", ms / 1000);
}

std::string heard_words(const LineHeard& h, const std::string& port) {
  switch (h.kind) {
    case LineHeard::Kind::Nothing: return fmt::format("nothing arrived from {}", port);
    case LineHeard::Kind::Noise:
      return fmt::format("{} bytes arrived from {}, none of them a valid frame (another baud rate, or not an nlsoft "
                         "firmware?)", h.bytes, port);
    case LineHeard::Kind::Echo:
      return fmt::format("the console's own frames came back from {} ({} of them) and nothing else: the line echoes "
                         "what is sent (a loopback, a terminal in echo mode, or a pseudo-terminal with nothing at its "
                         "other end), no firmware answers there",
                         port, h.frames);
    case LineHeard::Kind::OtherVersion:
      return fmt::format("the firmware at {} speaks protocol v{}, this console {}", port, h.version,
                         protocol_version_text());
    case LineHeard::Kind::Frames: break;
  }
  return "";
}

const char* link_event_name(LinkEvent::Kind k) {
  switch (k) {
    case LinkEvent::Kind::Down: return "down";
    case LinkEvent::Kind::Up: return "up";
    case LinkEvent::Kind::Silent: return "silent";
    case LinkEvent::Kind::Resumed: return "resumed";
    case LinkEvent::Kind::Foreign: return "foreign";
    case LinkEvent::Kind::Refused: return "refused";
  }
  return "?";
}

std::string down_words(const std::string& port, const std::string& why) { return fmt::format("{}: {}", port, why); }

std::string reopened_words(const std::string& port) { return port + " reopened"; }

std::string same_device_words(const std::string& port) { return port + " reopened, the same device answers"; }

std::string silence_words(bool silent, std::chrono::milliseconds limit, bool echoing,
                          const std::vector<PortOpener>& others) {
  if (!silent) return "frames arriving again";
  std::string detail = fmt::format("no valid frame for {} ms", limit.count());
  if (echoing) detail += "; only the console's own frames come back: the line echoes";
  if (!others.empty()) detail += "; " + also_open_words(others, "the port");
  return detail;
}

std::string no_reply_words(const NoReply& r) {
  const char* type = p::message_name(r.type);
  const std::string waited = wait_words(r.waited);
  // The tries and the time actually waited: --timeout is per try.
  const std::string each = fmt::format("{} ms each", r.per_try.count());
  std::string why =
      r.sent == 0 ? fmt::format("{} not sent: {} was down for all {} tries ({} in all)", type, r.port, r.tries, waited)
      : r.sent == r.tries
          ? fmt::format("no reply to {} after {} {}, {} ({} in all)", type, r.sent, r.sent == 1 ? "try" : "tries", each,
                        waited)
          : fmt::format("no reply to {}: {} of {} tries sent ({} was down for the others), {} ({} in all)", type,
                        r.sent, r.tries, r.port, each, waited);
  bool said_version = false;
  if (r.heard) {
    const LineHeard& h = *r.heard;
    said_version = h.kind == LineHeard::Kind::OtherVersion;
    if (h.kind == LineHeard::Kind::Nothing)
      why += "; " + heard_words(h, r.port) + ": is the firmware running? (a slow device needs a longer --timeout)";
    else if (h.kind != LineHeard::Kind::Frames)
      why += "; " + heard_words(h, r.port);
  }
  if (!r.others.empty()) why += "; " + also_open_words(r.others, r.port) + " and takes bytes meant for this console";
  if (!r.up) {
    why += r.will_reopen ? fmt::format("; {} is down, reconnecting", r.port)
                         : fmt::format("; {} is down for good (a pseudo-terminal does not come back)", r.port);
  } else if (r.unchecked) {
    why += fmt::format("; {} reopened, waiting for the device to identify itself", r.port);
  } else if (!r.foreign.empty()) {
    why += "; " + r.foreign;
  }
  if (r.foreign_version != 0 && !said_version)
    why += fmt::format("; the firmware speaks protocol v{}, this console {}", r.foreign_version, protocol_version_text());
  return why;
}

std::string no_info_words(const LineHeard& h, const std::string& port, std::chrono::steady_clock::duration waited,
                          unsigned baud, bool up) {
  std::string why = fmt::format("no INFO in {} of asking: ", wait_words(waited));
  switch (h.kind) {
    case LineHeard::Kind::Nothing:
      why += heard_words(h, port) + fmt::format(": is the firmware running, at {} baud?", baud);
      break;
    case LineHeard::Kind::Noise: why += heard_words(h, port) + fmt::format("; read at {} baud", baud); break;
    case LineHeard::Kind::Frames:
      why += fmt::format("{} frames arrived from {}, none of them an answer to INFO_GET", h.frames, port);
      break;
    default: why += heard_words(h, port);
  }
  if (!up) why += fmt::format("; {} is down", port);
  return why;
}

std::string unencodable_words(uint8_t type) {
  return fmt::format("cannot encode {}: payload breaks the message's length rule", p::message_name(type));
}

std::string unexpected_reply_words(uint8_t reply_type, size_t length, uint8_t request_type) {
  return fmt::format("unexpected reply {} ({} bytes) to {}", p::message_name(reply_type), length,
                     p::message_name(request_type));
}

}  // namespace nlsoft::console
