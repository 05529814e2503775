#pragma once
// Failures of a request to the firmware, typed so callers can tell a refusal
// (the firmware answered and changed nothing) from a broken link.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "protocol/messages.hpp"

namespace nlsoft::console {

// No reply after every retry, the port is gone, or the peer spoke nonsense.
struct LinkError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The firmware answered with NACK. what() is already in words; the raw
// fields stay available for callers that render their own message (the
// parameter panel names the element and its range).
struct NackError : std::runtime_error {
  NackError(const protocol::Nack& n, const std::string& words)
      : std::runtime_error(words), nack(n) {}
  protocol::Nack nack;
  protocol::StatusCode status() const { return protocol::StatusCode(nack.status); }
};

// "out of range", "not a finite number", ...: the status as a phrase.
std::string status_words(uint8_t status);

// The name of field #index of a request type ("values" for PARAM_SET #1),
// or "field N" when the type or index is unknown.
std::string request_field_name(uint8_t request_type, uint8_t field);

// Message name from the catalogue ("PARAM_SET"), or "type 0xNN".
std::string message_name(uint8_t type);

// "PARAM_SET refused: out of range (values[1])".
std::string describe_nack(const protocol::Nack& nack);

}  // namespace nlsoft::console
