#pragma once
// Host-only reader for golden.txt (format described at the top of that file
// and in PROTOCOL.md, "Golden vectors"), plus the canonical event list a
// decoder must produce for a vector's wire bytes. Firmware and console tests
// include this to hold their own peers against the same vectors.

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "protocol/decoder.hpp"
#include "protocol/status.hpp"
#include "protocol/host/message_text.hpp"

namespace nlsoft::protocol::golden {

struct Vector {
  std::string name;
  std::string note;
  std::vector<uint8_t> wire;
  // One per decoder event, in order: "frame <TYPE seq=.. flags=.. fields>"
  // or "error <reason>".
  std::vector<std::string> expect;
  int line = 0;  // where the vector starts, for failure messages
};

inline bool parse_hex_bytes(const std::string& s, std::vector<uint8_t>& out) {
  std::istringstream in(s);
  std::string tok;
  while (in >> tok) {
    if (tok.size() != 2) return false;
    char* end = nullptr;
    const unsigned long v = std::strtoul(tok.c_str(), &end, 16);
    if (*end != '\0') return false;
    out.push_back(static_cast<uint8_t>(v));
  }
  return true;
}

inline bool read_file(const std::string& path, std::vector<Vector>& out, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = "cannot open " + path;
    return false;
  }
  std::string line;
  int number = 0;
  Vector* cur = nullptr;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    const size_t colon = line.find(':');
    if (colon == std::string::npos) {
      error = path + ":" + std::to_string(number) + ": expected 'key: value'";
      return false;
    }
    const std::string key = line.substr(0, colon);
    size_t start = colon + 1;
    while (start < line.size() && line[start] == ' ') ++start;
    const std::string value = line.substr(start);
    if (key == "vector") {
      out.push_back(Vector{});
      cur = &out.back();
      cur->name = value;
      cur->line = number;
      continue;
    }
    if (cur == nullptr) {
      error = path + ":" + std::to_string(number) + ": '" + key + "' before any 'vector:'";
      return false;
    }
    if (key == "note") {
      cur->note += (cur->note.empty() ? "" : " ") + value;
    } else if (key == "wire") {
      if (!parse_hex_bytes(value, cur->wire)) {
        error = path + ":" + std::to_string(number) + ": bad hex";
        return false;
      }
    } else if (key == "expect") {
      cur->expect.push_back(value);
    } else {
      error = path + ":" + std::to_string(number) + ": unknown key '" + key + "'";
      return false;
    }
  }
  return true;
}

inline std::string describe(const DecodeResult& r) {
  if (r.kind == DecodeResult::Kind::Frame) return "frame " + text::format_frame(r.frame);
  return std::string("error ") + to_string(r.error);
}

// Feeds the bytes in pieces of `chunk` (0 = all at once) and lists the events.
inline std::vector<std::string> decode_events(const std::vector<uint8_t>& wire, size_t chunk = 0) {
  std::vector<std::string> events;
  Decoder decoder;
  size_t pos = 0;
  while (pos < wire.size()) {
    size_t avail = wire.size() - pos;
    if (chunk != 0 && avail > chunk) avail = chunk;
    DecodeResult r;
    pos += decoder.feed(wire.data() + pos, avail, r);
    if (r.kind != DecodeResult::Kind::None) events.push_back(describe(r));
  }
  return events;
}

}  // namespace nlsoft::protocol::golden
