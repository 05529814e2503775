#pragma once
// Host-only: a one-line text form of messages, used by the golden vectors,
// the console's protocol trace and test diagnostics. Not for the MCU (it
// uses std::string).
//
//   PING seq=1 flags=0 nonce=305419896
//   PARAM_SET seq=7 flags=0 id=3 values=1000000,2000000,1000000
//   LOG seq=3 flags=0 level=2 text="loop overrun at step 12"
//
// Values: integers in decimal; floats with 9 significant digits (enough to
// round-trip binary32 exactly) or, when not finite, their bit pattern as
// 0xXXXXXXXX; PARAM_SET/PARAM_VALUE words print as floats when they are a
// normal float or zero and as 0xXXXXXXXX bit patterns otherwise (integer
// parameters, NaN); byte arrays as contiguous hex; text in double quotes with
// \\, \" and \xHH escapes; arrays comma-separated, empty array = nothing
// after '='. Fields appear in wire order.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "protocol/catalog.hpp"
#include "protocol/frame.hpp"
#include "protocol/messages.hpp"

namespace nlsoft::protocol::text {

namespace detail {

inline std::string format_float(float x) {
  char buf[32];
  if (std::isfinite(x)) {
    std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(x));
  } else {
    uint32_t bits;
    std::memcpy(&bits, &x, 4);
    std::snprintf(buf, sizeof buf, "0x%08x", bits);
  }
  return buf;
}

inline std::string format_word(uint32_t w, ParamType type) {
  char buf[32];
  if (type == ParamType::F32) {
    const uint32_t exponent = (w >> 23) & 0xFFu;
    const bool zero = (w & 0x7FFFFFFFu) == 0;
    if (zero || (exponent != 0 && exponent != 0xFF)) {
      float x;
      std::memcpy(&x, &w, 4);
      return format_float(x);
    }
    std::snprintf(buf, sizeof buf, "0x%08x", w);
    return buf;
  }
  std::snprintf(buf, sizeof buf, "%u", w);
  return buf;
}

inline std::string quote(const char* s) {
  std::string out = "\"";
  for (const char* p = s; *p; ++p) {
    const auto c = static_cast<unsigned char>(*p);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += static_cast<char>(c);
    } else if (c < 0x20 || c >= 0x7F) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out + "\"";
}

class FormatVisitor {
 public:
  std::string out;

  void u8(const char* k, uint8_t x) { put(k, std::to_string(x)); }
  void u16(const char* k, uint16_t x) { put(k, std::to_string(x)); }
  void u32(const char* k, uint32_t x) { put(k, std::to_string(x)); }
  void f32(const char* k, float x) { put(k, format_float(x)); }
  void nibbles(const char* kh, uint8_t hi, const char* kl, uint8_t lo) {
    u8(kh, hi);
    u8(kl, lo);
  }
  void f32_array(const char* k, const float* a, uint8_t count, uint8_t) {
    std::string v;
    for (uint8_t i = 0; i < count; ++i) v += (i ? "," : "") + format_float(a[i]);
    put(k, v);
  }
  void f32_tail(const char* k, const float* a, uint8_t count, uint8_t cap) {
    f32_array(k, a, count, cap);
  }
  void word_tail(const char* k, const uint32_t* a, uint8_t count, uint8_t, ParamType type) {
    std::string v;
    for (uint8_t i = 0; i < count; ++i) v += (i ? "," : "") + format_word(a[i], type);
    put(k, v);
  }
  void bytes_tail(const char* k, const uint8_t* a, uint8_t size, uint8_t) {
    std::string v;
    char buf[4];
    for (uint8_t i = 0; i < size; ++i) {
      std::snprintf(buf, sizeof buf, "%02x", a[i]);
      v += buf;
    }
    put(k, v);
  }
  void text_tail(const char* k, const char* s, uint8_t) { put(k, quote(s)); }
  void text_fixed(const char* k, const char* s, uint8_t) { put(k, quote(s)); }

 private:
  void put(const char* k, const std::string& v) {
    out += ' ';
    out += k;
    out += '=';
    out += v;
  }
};

inline bool parse_u32(const std::string& s, uint32_t max, uint32_t& out) {
  if (s.empty() || s[0] == '-') return false;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(s.c_str(), &end, 0);
  if (*end != '\0' || v > max) return false;
  out = static_cast<uint32_t>(v);
  return true;
}

inline bool parse_float(const std::string& s, float& out) {
  if (s.size() > 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X')) {
    uint32_t bits;
    if (!parse_u32(s, 0xFFFFFFFFu, bits)) return false;
    std::memcpy(&out, &bits, 4);
    return true;
  }
  if (s.empty()) return false;
  char* end = nullptr;
  out = std::strtof(s.c_str(), &end);
  return *end == '\0';
}

inline std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> items;
  if (s.empty()) return items;
  size_t start = 0;
  for (;;) {
    const size_t comma = s.find(',', start);
    items.push_back(s.substr(start, comma == std::string::npos ? std::string::npos
                                                               : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return items;
}

class ParseVisitor {
 public:
  explicit ParseVisitor(std::map<std::string, std::string>& fields) : fields_(fields) {}
  std::string error;

  void u8(const char* k, uint8_t& x) { x = static_cast<uint8_t>(integer(k, 0xFF)); }
  void u16(const char* k, uint16_t& x) { x = static_cast<uint16_t>(integer(k, 0xFFFF)); }
  void u32(const char* k, uint32_t& x) { x = integer(k, 0xFFFFFFFFu); }
  void f32(const char* k, float& x) {
    std::string v;
    if (take(k, v) && !parse_float(v, x)) fail(k, "not a float");
  }
  void nibbles(const char* kh, uint8_t& hi, const char* kl, uint8_t& lo) {
    hi = static_cast<uint8_t>(integer(kh, 0x0F));
    lo = static_cast<uint8_t>(integer(kl, 0x0F));
  }
  void f32_array(const char* k, float* a, uint8_t count, uint8_t cap) {
    uint8_t got = 0;
    floats(k, a, got, cap);
    if (error.empty() && got != count) fail(k, "wrong element count");
  }
  void f32_tail(const char* k, float* a, uint8_t& count, uint8_t cap) { floats(k, a, count, cap); }
  void word_tail(const char* k, uint32_t* a, uint8_t& count, uint8_t cap, ParamType type) {
    std::string v;
    if (!take(k, v)) return;
    const auto items = split_list(v);
    if (items.size() > cap) return fail(k, "too many elements");
    count = static_cast<uint8_t>(items.size());
    for (size_t i = 0; i < items.size(); ++i) {
      const std::string& it = items[i];
      const bool hex = it.size() > 2 && it[0] == '0' && (it[1] == 'x' || it[1] == 'X');
      if (type == ParamType::F32 && !hex) {
        float x;
        if (!parse_float(it, x)) return fail(k, "not a float");
        std::memcpy(&a[i], &x, 4);
      } else if (!parse_u32(it, 0xFFFFFFFFu, a[i])) {
        return fail(k, "not a word");
      }
    }
  }
  void bytes_tail(const char* k, uint8_t* a, uint8_t& size, uint8_t cap) {
    std::string v;
    if (!take(k, v)) return;
    if (v.size() % 2 != 0 || v.size() / 2 > cap) return fail(k, "bad hex length");
    size = static_cast<uint8_t>(v.size() / 2);
    for (size_t i = 0; i < size; ++i) {
      uint32_t b;
      if (!parse_u32("0x" + v.substr(2 * i, 2), 0xFF, b)) return fail(k, "bad hex");
      a[i] = static_cast<uint8_t>(b);
    }
  }
  void text_tail(const char* k, char* s, uint8_t cap) { text(k, s, cap); }
  void text_fixed(const char* k, char* s, uint8_t size) { text(k, s, size); }

 private:
  bool take(const char* k, std::string& v) {
    if (!error.empty()) return false;
    auto it = fields_.find(k);
    if (it == fields_.end()) {
      fail(k, "missing");
      return false;
    }
    v = it->second;
    fields_.erase(it);
    return true;
  }
  uint32_t integer(const char* k, uint32_t max) {
    std::string v;
    uint32_t x = 0;
    if (take(k, v) && !parse_u32(v, max, x)) fail(k, "not an integer in range");
    return x;
  }
  void floats(const char* k, float* a, uint8_t& count, uint8_t cap) {
    std::string v;
    if (!take(k, v)) return;
    const auto items = split_list(v);
    if (items.size() > cap) return fail(k, "too many elements");
    count = static_cast<uint8_t>(items.size());
    for (size_t i = 0; i < items.size(); ++i) {
      if (!parse_float(items[i], a[i])) return fail(k, "not a float");
    }
  }
  void text(const char* k, char* s, uint8_t cap) {
    std::string v;
    if (!take(k, v)) return;
    if (v.size() < 2 || v.front() != '"' || v.back() != '"') return fail(k, "not quoted");
    std::string out;
    for (size_t i = 1; i + 1 < v.size(); ++i) {
      if (v[i] != '\\') {
        out += v[i];
        continue;
      }
      if (i + 2 >= v.size()) return fail(k, "bad escape");
      const char e = v[++i];
      if (e == 'x') {
        uint32_t b;
        if (i + 3 >= v.size() || !parse_u32("0x" + v.substr(i + 1, 2), 0xFF, b)) {
          return fail(k, "bad escape");
        }
        out += static_cast<char>(b);
        i += 2;
      } else {
        out += e;
      }
    }
    if (out.size() > cap) return fail(k, "text too long");
    std::memcpy(s, out.data(), out.size());
    s[out.size()] = '\0';
  }
  void fail(const char* k, const char* why) {
    if (error.empty()) error = std::string(k) + ": " + why;
  }

  std::map<std::string, std::string>& fields_;
};

// Splits "a=1 b="x y" c=" into key/value pairs; quotes protect spaces.
inline bool split_fields(const std::string& s, size_t pos,
                         std::map<std::string, std::string>& out, std::string& error) {
  while (pos < s.size()) {
    while (pos < s.size() && s[pos] == ' ') ++pos;
    if (pos >= s.size()) break;
    const size_t eq = s.find('=', pos);
    if (eq == std::string::npos) {
      error = "field without '=' at: " + s.substr(pos);
      return false;
    }
    const std::string key = s.substr(pos, eq - pos);
    size_t end = eq + 1;
    if (end < s.size() && s[end] == '"') {
      ++end;
      while (end < s.size() && s[end] != '"') end += (s[end] == '\\') ? 2 : 1;
      if (end >= s.size()) {
        error = "unterminated string in " + key;
        return false;
      }
      ++end;
    } else {
      while (end < s.size() && s[end] != ' ') ++end;
    }
    if (!out.emplace(key, s.substr(eq + 1, end - eq - 1)).second) {
      error = "duplicate field " + key;
      return false;
    }
    pos = end;
  }
  return true;
}

}  // namespace detail

template <class M>
std::string format_fields(const M& msg) {
  detail::FormatVisitor v;
  M::fields(msg, v);
  return v.out;
}

// "TYPE seq=S flags=F field=value ..." for a decoded frame.
inline std::string format_frame(const FrameView& frame) {
  std::string out = message_name(frame.header.type);
  out += " seq=" + std::to_string(frame.header.seq) +
         " flags=" + std::to_string(frame.header.flags);
  const bool known = with_message_type(frame.header.type, [&](auto msg) {
    if (unpack(frame, msg) == StatusCode::Ok) {
      out += format_fields(msg);
    } else {
      out += " <unpack failed>";
    }
  });
  if (!known) out += " <unknown type>";
  return out;
}

struct ParsedFrame {
  uint8_t type = 0;
  uint8_t seq = 0;
  uint8_t flags = 0;
  std::vector<uint8_t> payload;
};

// Inverse of format_frame. Every field must be present exactly once and no
// other may appear, so a typo in a vector file cannot pass silently.
inline bool parse_frame(const std::string& line, ParsedFrame& out, std::string& error) {
  error.clear();
  out = ParsedFrame{};
  const size_t sp = line.find(' ');
  const std::string name = line.substr(0, sp);
  const MsgInfo* info = nullptr;
  for (const MsgInfo& m : kMessages) {
    if (name == m.name) info = &m;
  }
  if (info == nullptr) {
    error = "unknown message name " + name;
    return false;
  }
  std::map<std::string, std::string> fields;
  if (sp != std::string::npos && !detail::split_fields(line, sp, fields, error)) return false;
  detail::ParseVisitor header(fields);
  header.u8("seq", out.seq);
  header.u8("flags", out.flags);
  if (!header.error.empty()) {
    error = header.error;
    return false;
  }
  out.type = static_cast<uint8_t>(info->type);
  with_message_type(out.type, [&](auto msg) {
    detail::ParseVisitor v(fields);
    decltype(msg)::fields(msg, v);
    if (!v.error.empty()) {
      error = v.error;
      return;
    }
    out.payload.resize(kMaxPayload);
    size_t len = 0;
    if (pack(msg, out.payload.data(), out.payload.size(), len) != StatusCode::Ok) {
      error = "fields do not pack into a valid payload";
      return;
    }
    out.payload.resize(len);
  });
  if (error.empty() && !fields.empty()) error = "unexpected field " + fields.begin()->first;
  return error.empty();
}

}  // namespace nlsoft::protocol::text
