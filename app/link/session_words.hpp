#pragma once
// The session's facts in a user's words: a request left unanswered, a
// device that never identified itself, a silent line, a port reopened on
// another device. The session holds the protocol's mechanics and hands its
// facts here; every message session.cpp gives is written in this file's .cpp.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "app/link/port_openers.hpp"
#include "app/link/session.hpp"
#include "protocol/messages.hpp"

namespace nlsoft::console {

// heard_words, wait_words and link_event_name, declared with the facts they
// say in session.hpp, are written in this file's .cpp too.

// INFO's platform byte in words: the shipped rig whose file gives it that
// number (rigs/*.toml info_platform), "custom" for 255, else "#N".
std::string platform_words(uint8_t platform);

// How `now` is not the device `was`, in words; empty if it is the same one.
// The same device is the same rig and firmware build. Not compared: uptime
// (a board that reset is still the same board), model_hash and param_hash
// (an upload changes them; the console re-reads both after a reconnect),
// loop rate and capabilities. INFO carries no serial number, so two boards
// of one build on one rig cannot be told apart.
std::string identity_change(const protocol::Info& was, const protocol::Info& now);
// A reopened port's peer that answered INFO_GET with something else.
std::string not_info_words(uint8_t reply_type);
// Why a reopened port's peer is refused: "a different device now answers at PORT: CHANGE".
std::string foreign_words(const std::string& port, const std::string& change);

// Event details.
std::string down_words(const std::string& port, const std::string& why);
std::string reopened_words(const std::string& port);
std::string same_device_words(const std::string& port);
// The silence began (no valid frame for `limit`), or ended (`silent` false).
std::string silence_words(bool silent, std::chrono::milliseconds limit, bool echoing,
                          const std::vector<PortOpener>& others);

// A request that got no reply after every try, and what the line did meanwhile.
struct NoReply {
  uint8_t type = 0;  // the request
  int sent = 0, tries = 0;
  std::chrono::milliseconds per_try{0};
  std::chrono::steady_clock::duration waited{};
  std::string port;
  bool up = false, will_reopen = false;
  bool unchecked = false;       // reopened, the device not identified yet
  std::string foreign;          // the refusal of another device, when one answers
  std::optional<LineHeard> heard;  // on an up link to the known device
  std::vector<PortOpener> others;  // other programs with the port open (idem)
  uint8_t foreign_version = 0;  // the protocol version of frames dropped, 0: none
};
std::string no_reply_words(const NoReply& r);

// "no INFO in 3.0 s of asking: nothing arrived from PORT: is the firmware
// running, at 115200 baud?": why a device never identified itself.
std::string no_info_words(const LineHeard& h, const std::string& port, std::chrono::steady_clock::duration waited,
                          unsigned baud, bool up);

// A request whose payload cannot be framed.
std::string unencodable_words(uint8_t type);
std::string unexpected_reply_words(uint8_t reply_type, size_t length, uint8_t request_type);

}  // namespace nlsoft::console
