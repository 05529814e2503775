#include "app/live/conformance.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "app/cli_error.hpp"
#include "app/link/link_error.hpp"
#include "app/link/serial_link.hpp"
#include "app/link/sim_launcher.hpp"
#include "protocol/crc.hpp"
#include "protocol/decoder.hpp"
#include "protocol/encoder.hpp"

namespace nlsoft::console {

namespace {

namespace p = nlsoft::protocol;
using Clock = std::chrono::steady_clock;
using Ms = std::chrono::milliseconds;

struct ConformanceArgs {
  std::string port, sim;
  unsigned baud = 115200;
  bool json = false;
  int timeout_ms = 250;
};

// A decoded frame, copied off the I/O thread.
struct Frame {
  p::Header header;
  std::vector<uint8_t> payload;
  bool is_reply() const { return (header.flags & p::frame_flags::kReply) != 0; }
};

template <class M>
bool as(const Frame& f, M& m) {
  return f.header.type == uint8_t(M::kType) && p::unpack(f.payload.data(), f.payload.size(), m) == p::StatusCode::Ok;
}

// "PONG", "NACK: PARAM_SET refused: out of range (values[0])".
std::string describe(const Frame& f) {
  p::Nack n;
  if (as(f, n)) return "NACK: " + describe_nack(n);
  return message_name(f.header.type);
}

// The reply types a request may get (PROTOCOL.md section 6).
bool answers(uint8_t request, const Frame& f) {
  const uint8_t t = f.header.type;
  if (t == uint8_t(p::MsgType::Ack) || t == uint8_t(p::MsgType::Nack))
    return !f.payload.empty() && f.payload[0] == request;
  switch (p::MsgType(request)) {
    case p::MsgType::Ping: return t == uint8_t(p::MsgType::Pong);
    case p::MsgType::InfoGet: return t == uint8_t(p::MsgType::Info);
    case p::MsgType::ParamList: return t == uint8_t(p::MsgType::ParamDesc);
    case p::MsgType::ParamGet:
    case p::MsgType::ParamSet: return t == uint8_t(p::MsgType::ParamValue);
    case p::MsgType::XferBegin:
    case p::MsgType::XferChunk: return t == uint8_t(p::MsgType::XferAck);
    // The heartbeat is a STATUS too: only one flagged as a reply answers.
    case p::MsgType::StatusGet: return t == uint8_t(p::MsgType::Status) && f.is_reply();
    default: return false;
  }
}

// The wire end of the suite: its own decoder over SerialLink, so it can pick
// sequence numbers (duplicates) and send frames no Session would (bad CRC,
// unknown type, garbage). Stop-and-wait with retransmission, as section 10.
class Probe {
 public:
  struct TelemetrySample {
    uint16_t tseq;
    uint32_t step;
  };

  explicit Probe(Ms timeout) : timeout_(timeout) {}
  ~Probe() { link_.close(); }

  void open(const std::string& path, unsigned baud) {
    SerialLink::Handlers h;
    h.on_bytes = [this](const uint8_t* d, size_t n) { on_bytes(d, n); };
    h.on_down = [this](const std::string&) { decoder_.reset(); };
    h.on_up = [] {};
    link_.open(path, baud, std::move(h));
    link_.write({p::kDelimiter});  // ends whatever partial frame the peer holds
  }

  uint8_t next_seq() { return seq_++; }
  Ms timeout() const { return timeout_; }

  static std::vector<uint8_t> wire(uint8_t type, uint8_t seq, const uint8_t* payload, size_t len) {
    uint8_t buf[p::kWireBufferSize];
    const size_t n = p::encode_frame(type, seq, 0, payload, len, buf, sizeof buf);
    if (n == 0) throw LinkError(fmt::format("cannot encode a {} frame", message_name(type)));
    return {buf, buf + n};
  }

  template <class Req>
  static std::vector<uint8_t> wire(const Req& req, uint8_t seq) {
    uint8_t payload[p::kMaxPayload];
    payload[0] = 0;
    size_t len = 0;
    if (p::pack(req, payload, sizeof payload, len) != p::StatusCode::Ok)
      throw LinkError(fmt::format("cannot encode {}", message_name(uint8_t(Req::kType))));
    return wire(uint8_t(Req::kType), seq, payload, len);
  }

  // A request with a fresh seq; returns the frame that answers it.
  template <class Req>
  Frame request(const Req& req, int tries = 4) {
    const uint8_t seq = next_seq();
    return exchange(uint8_t(Req::kType), seq, wire(req, seq), tries);
  }

  // Sends `bytes` (a request of `type` numbered `seq`) and waits for the
  // answer, retransmitting unchanged. A frame of the answering type with the
  // wrong seq or without REPLY is taken only when nothing better comes, and
  // counted against the firmware.
  Frame exchange(uint8_t type, uint8_t seq, const std::vector<uint8_t>& bytes, int tries = 4) {
    {
      std::lock_guard<std::mutex> lock(mu_);
      frames_.clear();
    }
    for (int t = 0; t < tries; ++t) {
      link_.write(bytes);
      std::optional<Frame> candidate;
      const auto deadline = Clock::now() + timeout_;
      std::unique_lock<std::mutex> lock(mu_);
      while (true) {
        while (!frames_.empty()) {
          Frame f = std::move(frames_.front());
          frames_.pop_front();
          if (!answers(type, f)) continue;
          ++replies_;
          if (f.header.seq == seq && f.is_reply()) return f;
          if (!candidate) candidate = std::move(f);
        }
        if (cv_.wait_until(lock, deadline) == std::cv_status::timeout && frames_.empty()) break;
      }
      if (candidate) {
        ++bad_replies_;
        if (first_bad_.empty())
          first_bad_ = fmt::format("{} seq {} answered by {} with seq {} flags 0x{:02x}", message_name(type), seq,
                                   message_name(candidate->header.type), candidate->header.seq,
                                   candidate->header.flags);
        return *candidate;
      }
    }
    throw LinkError(fmt::format("no reply to {} after {} tries of {} ms", message_name(type), tries, timeout_.count()));
  }

  // Sends bytes that must get no reply; returns a description of any reply
  // that arrives within `quiet`, or nothing.
  std::optional<std::string> expect_silence(const std::vector<uint8_t>& bytes, Ms quiet) {
    {
      std::lock_guard<std::mutex> lock(mu_);
      frames_.clear();
    }
    link_.write(bytes);
    std::this_thread::sleep_for(quiet);
    std::lock_guard<std::mutex> lock(mu_);
    for (const Frame& f : frames_)
      if (f.is_reply()) return fmt::format("{} seq {}", describe(f), f.header.seq);
    return std::nullopt;
  }

  void record_telemetry(bool on) {
    std::lock_guard<std::mutex> lock(mu_);
    recording_ = on;
    if (on) telemetry_.clear();
  }
  std::vector<TelemetrySample> telemetry() {
    std::lock_guard<std::mutex> lock(mu_);
    return telemetry_;
  }
  unsigned replies() const { return replies_; }
  unsigned bad_replies() const { return bad_replies_; }
  const std::string& first_bad() const { return first_bad_; }

 private:
  void on_bytes(const uint8_t* data, size_t len) {
    size_t used = 0;
    while (used < len) {
      p::DecodeResult r;
      used += decoder_.feed(data + used, len - used, r);
      if (r.kind != p::DecodeResult::Kind::Frame) continue;
      const p::FrameView& f = r.frame;
      if (f.header.type == uint8_t(p::MsgType::Log)) continue;
      if (f.header.type == uint8_t(p::MsgType::Telemetry)) {
        p::Telemetry t;
        std::lock_guard<std::mutex> lock(mu_);
        if (recording_ && p::unpack(f, t) == p::StatusCode::Ok) telemetry_.push_back({t.tseq, t.step});
        continue;
      }
      Frame copy;
      copy.header = f.header;
      copy.payload.assign(f.payload, f.payload + f.payload_size());
      {
        std::lock_guard<std::mutex> lock(mu_);
        frames_.push_back(std::move(copy));
        if (frames_.size() > 512) frames_.pop_front();
      }
      cv_.notify_all();
    }
  }

  Ms timeout_;
  SerialLink link_;
  p::Decoder decoder_;  // I/O thread only
  std::mutex mu_;
  std::condition_variable cv_;
  std::deque<Frame> frames_;
  bool recording_ = false;
  std::vector<TelemetrySample> telemetry_;
  uint8_t seq_ = 0;
  unsigned replies_ = 0, bad_replies_ = 0;
  std::string first_bad_;
};

struct CheckResult {
  std::string name;
  bool pass;
  std::string detail;
};

std::string json_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '"' || c == '\\')
      o += '\\', o += c;
    else if (static_cast<unsigned char>(c) < 0x20)
      o += fmt::format("\\u{:04x}", int(c));
    else
      o += c;
  }
  return o;
}

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string o;
  for (size_t i = 0; i < v.size(); ++i) o += (i ? sep : "") + v[i];
  return o;
}

float word_f32(uint32_t w) {
  float x;
  std::memcpy(&x, &w, 4);
  return x;
}
uint32_t f32_word(float x) {
  uint32_t w;
  std::memcpy(&w, &x, 4);
  return w;
}

std::string words_text(const uint32_t* v, uint8_t count, uint8_t type) {
  std::string s;
  for (uint8_t i = 0; i < count; ++i) {
    if (i) s += ' ';
    s += type == uint8_t(p::ParamType::F32) ? fmt::format("{:g}", word_f32(v[i])) : fmt::format("{}", v[i]);
  }
  return s;
}

class Suite {
 public:
  Suite(Probe& probe, bool json) : pr_(probe), json_(json) {}

  void run(std::chrono::seconds patience) {
    handshake(patience);
    try {
      status_and_ping();
      params();
      duplicate();
      malformed();
      run_control();
      transfers();
    } catch (const LinkError&) {
      restore();
      throw;
    }
    restore();
    check("reply_seq", pr_.bad_replies() == 0,
          pr_.bad_replies() == 0
              ? fmt::format("{} replies, each with the request's seq and REPLY set", pr_.replies())
              : fmt::format("{} of {} replies wrong; first: {}", pr_.bad_replies(), pr_.replies(), pr_.first_bad()));
  }

  const std::vector<CheckResult>& results() const { return results_; }

 private:
  void check(const std::string& name, bool pass, const std::string& detail) {
    results_.push_back({name, pass, detail});
    if (!json_) std::printf("%s %s: %s\n", pass ? "PASS" : "FAIL", name.c_str(), detail.c_str()), std::fflush(stdout);
  }

  // ------------------------------------------------------------ handshake
  void handshake(std::chrono::seconds patience) {
    const auto give_up = Clock::now() + patience;
    Frame f;
    while (true) {
      try {
        f = pr_.request(p::InfoGet{}, 1);
        break;
      } catch (const LinkError&) {
        if (Clock::now() >= give_up)
          throw LinkError(fmt::format("no INFO for {} s: is the firmware running at this baud rate?", patience.count()));
      }
    }
    if (!as(f, info_)) {
      check("handshake", false, "INFO_GET answered by " + describe(f));
      throw LinkError("no usable INFO: cannot go on");
    }
    std::vector<std::string> bad;
    if (info_.protocol_version != 1) bad.push_back(fmt::format("protocol_version {}", info_.protocol_version));
    if (info_.n < 1 || info_.n > p::kMaxTelemetryDim) bad.push_back(fmt::format("n {}", info_.n));
    if (info_.m < 1 || info_.m > p::kMaxTelemetryDim) bad.push_back(fmt::format("m {}", info_.m));
    if (info_.max_n < 1 || info_.max_nc < 1 || info_.max_nc > info_.max_n)
      bad.push_back(fmt::format("max_n {} max_nc {}", info_.max_n, info_.max_nc));
    if (info_.loop_rate_hz == 0) bad.push_back("loop_rate_hz 0");
    if (info_.platform > 2 && info_.platform != 255) bad.push_back(fmt::format("platform {}", info_.platform));
    const std::string what = fmt::format("{} {}.{}.{}, protocol {}, platform {}, n={} m={} max_n={} max_nc={}, {} Hz",
                                         info_.firmware, info_.fw_major, info_.fw_minor, info_.fw_patch,
                                         info_.protocol_version, info_.platform, info_.n, info_.m, info_.max_n,
                                         info_.max_nc, info_.loop_rate_hz);
    check("handshake", bad.empty(), bad.empty() ? what : "implausible " + join(bad, ", ") + " (" + what + ")");
    if (info_.protocol_version != 1) throw LinkError("firmware speaks another protocol version");
  }

  std::optional<p::Status> status() {
    const Frame f = pr_.request(p::StatusGet{});
    p::Status s;
    if (!as(f, s)) return std::nullopt;
    return s;
  }

  uint32_t nonce() { return uint32_t(rng_()); }

  void status_and_ping() {
    const Frame f = pr_.request(p::StatusGet{});
    p::Status s;
    if (as(f, s)) {
      std::string note;
      if (s.run_state != uint8_t(p::RunState::Idle)) {
        // A run left active would make "only while stopped" parameters refuse.
        const Frame stop = pr_.request(p::RunStop{});
        note = fmt::format("; run {} was active (state {}), stopped it: {}", s.run_id, s.run_state, describe(stop));
      }
      telemetry_mask_ = s.telemetry_mask;
      check("status_get", true,
            fmt::format("STATUS uptime {} ms, run_state {}, frames_in {}{}", s.uptime_ms, s.run_state, s.frames_in, note));
    } else {
      check("status_get", false, "STATUS_GET answered by " + describe(f));
    }

    p::Ping ping;
    ping.nonce = nonce();
    const Frame g = pr_.request(ping);
    p::Pong pong;
    if (!as(g, pong))
      check("ping", false, "PING answered by " + describe(g));
    else
      check("ping", pong.nonce == ping.nonce,
            fmt::format("nonce 0x{:08x} sent, 0x{:08x} echoed, uptime {} ms", ping.nonce, pong.nonce, pong.uptime_ms));
  }

  // ----------------------------------------------------------- parameters
  std::optional<p::ParamValue> get(uint16_t id) {
    p::ParamGet g;
    g.id = id;
    const Frame f = pr_.request(g);
    p::ParamValue v;
    if (!as(f, v)) return std::nullopt;
    return v;
  }

  static bool same(const p::ParamValue& a, const p::ParamValue& b) {
    return a.count == b.count && std::memcmp(a.values, b.values, 4u * a.count) == 0;
  }

  void params() {
    // PARAM_LIST: count from the first descriptor, then every index.
    std::vector<std::string> bad;
    uint16_t count = 1;
    std::set<uint16_t> ids;
    for (uint16_t i = 0; i < count; ++i) {
      p::ParamList l;
      l.index = i;
      const Frame f = pr_.request(l);
      p::ParamDesc d;
      if (!as(f, d)) {
        bad.push_back(fmt::format("index {}: {}", i, describe(f)));
        break;
      }
      if (i == 0) count = d.count;
      if (d.index != i) bad.push_back(fmt::format("index {} answered as {}", i, d.index));
      if (d.count != count) bad.push_back(fmt::format("index {}: count {} (was {})", i, d.count, count));
      if (d.size < 1 || d.size > p::kMaxParamValues) bad.push_back(fmt::format("{}: size {}", d.name, d.size));
      if (!ids.insert(d.id).second) bad.push_back(fmt::format("id {} twice", d.id));
      descs_.push_back(d);
    }
    check("param_list", bad.empty() && !descs_.empty(),
          bad.empty() ? fmt::format("{} descriptors", descs_.size()) : join(bad, "; "));
    {
      p::ParamList l;
      l.index = count;
      const Frame f = pr_.request(l);
      p::Nack n;
      const bool ok = as(f, n) && n.status == uint8_t(p::StatusCode::UnknownId) && n.field == 0;
      check("param_list_end", ok, fmt::format("PARAM_LIST({}) answered by {}", count, describe(f)));
    }

    // PARAM_GET of every id: the described type and size.
    bad.clear();
    for (const p::ParamDesc& d : descs_) {
      p::ParamGet g;
      g.id = d.id;
      const Frame f = pr_.request(g);
      p::ParamValue v;
      if (!as(f, v)) {
        bad.push_back(fmt::format("{}: {}", d.name, describe(f)));
        continue;
      }
      if (v.id != d.id || v.count != d.size || v.type != d.type)
        bad.push_back(fmt::format("{}: id {} type {} with {} values (described id {} type {} size {})", d.name, v.id,
                                  v.type, v.count, d.id, d.type, d.size));
      original_[d.id] = v;
    }
    check("param_get", bad.empty(),
          bad.empty() ? fmt::format("{} parameters, each of its described size", descs_.size())
                      : join(bad, "; "));

    param_set();
  }

  // The PARAM_SET checks need a writable f32 parameter: Q if there is one.
  const p::ParamDesc* pick_f32() const {
    const p::ParamDesc* pick = nullptr;
    for (const p::ParamDesc& d : descs_) {
      if (d.type != uint8_t(p::ParamType::F32) || (d.access & p::param_access::kReadOnly) ||
          original_.count(d.id) == 0)
        continue;
      if (std::strcmp(d.name, "Q") == 0) return &d;
      if (!pick) pick = &d;
    }
    return pick;
  }

  // PARAM_SET of `values` must be NACKed with `status` at (field, element)
  // and leave the parameter as it was.
  void refused(const std::string& name, const p::ParamDesc& d, const p::ParamSet& set, p::StatusCode status,
               uint8_t element, const std::string& what) {
    const Frame f = pr_.request(set);
    p::Nack n;
    const bool nacked = as(f, n) && n.status == uint8_t(status) && n.field == 1 && n.element == element;
    const auto now = get(d.id);
    const bool unchanged = now && same(*now, original_.at(d.id));
    if (!unchanged) touched_.insert(d.id);
    check(name, nacked && unchanged,
          fmt::format("{} {}: {}; value read back {}", d.name, what, describe(f),
                      !now ? "not readable" : unchanged ? "unchanged" : "CHANGED to " + words_text(now->values, now->count, now->type)));
  }

  void param_set() {
    const p::ParamDesc* dp = pick_f32();
    if (!dp) {
      for (const char* name : {"param_set_out_of_range", "param_set_not_finite", "param_set_wrong_size", "param_set_valid"})
        check(name, false, "no writable f32 parameter to try");
      return;
    }
    const p::ParamDesc& d = *dp;
    const p::ParamValue& orig = original_.at(d.id);
    p::ParamSet base;
    base.id = d.id;
    base.count = orig.count;
    std::memcpy(base.values, orig.values, 4u * orig.count);

    // Out of range: below min (Q = -1 for Q's min 0), else above max.
    const float big = std::numeric_limits<float>::max() / 4;
    std::optional<float> outside;
    if (std::isfinite(d.min) && d.min > -big)
      outside = d.min - std::max(1.0f, std::fabs(d.min));
    else if (std::isfinite(d.max) && d.max < big)
      outside = d.max + std::max(1.0f, std::fabs(d.max));
    if (outside) {
      p::ParamSet s = base;
      s.set_f32(0, *outside);
      refused("param_set_out_of_range", d, s, p::StatusCode::OutOfRange, 0,
              fmt::format("[0] = {:g} (range {:g}..{:g})", *outside, d.min, d.max));
    } else {
      check("param_set_out_of_range", true, fmt::format("{} is unbounded: nothing to try", d.name));
    }
    {
      p::ParamSet s = base;
      s.set_f32(0, std::numeric_limits<float>::quiet_NaN());
      refused("param_set_not_finite", d, s, p::StatusCode::NotFinite, 0, "[0] = NaN");
    }
    {
      p::ParamSet s = base;
      s.count = uint8_t(d.size < p::kMaxParamValues ? d.size + 1 : d.size - 1);
      for (uint8_t i = d.size; i < s.count; ++i) s.values[i] = orig.values[0];
      refused("param_set_wrong_size", d, s, p::StatusCode::WrongSize, p::kNoField,
              fmt::format("with {} values (size {})", s.count, d.size));
    }

    // A valid value: the reply is the value in force, and a read agrees.
    const float now = word_f32(orig.values[0]);
    std::vector<float> candidates = {now * 2, now / 2, (d.min + d.max) / 2, d.min, d.max, now + 1};
    std::string tried;
    for (float c : candidates) {
      if (!std::isfinite(c) || c < d.min || c > d.max || f32_word(c) == orig.values[0]) continue;
      p::ParamSet s = base;
      s.set_f32(0, c);
      touched_.insert(d.id);
      const Frame f = pr_.request(s);
      p::ParamValue echo;
      if (!as(f, echo)) {
        p::Nack n;
        if (as(f, n) && n.status == uint8_t(p::StatusCode::Inconsistent)) {  // a cross-parameter rule: next one
          tried += fmt::format(" {:g} inconsistent;", c);
          continue;
        }
        check("param_set_valid", false, fmt::format("{}[0] = {:g}: {}", d.name, c, describe(f)));
        return;
      }
      const auto back = get(d.id);
      const bool ok = echo.id == d.id && echo.count == d.size && back && same(*back, echo);
      check("param_set_valid", ok,
            fmt::format("{}[0] = {:g}: PARAM_VALUE {} in force{}; read back {}", d.name, c,
                        words_text(echo.values, echo.count, echo.type), f32_word(c) == echo.values[0] ? "" : " (adjusted)",
                        back ? words_text(back->values, back->count, back->type) : "nothing"));
      return;
    }
    check("param_set_valid", false, fmt::format("{}: no valid value accepted:{}", d.name, tried));
  }

  void restore() {
    std::vector<std::string> bad;
    for (uint16_t id : touched_) {
      const p::ParamValue& orig = original_.at(id);
      p::ParamSet s;
      s.id = id;
      s.count = orig.count;
      std::memcpy(s.values, orig.values, 4u * orig.count);
      try {
        pr_.request(s);
        const auto back = get(id);
        if (!back || !same(*back, orig)) bad.push_back(fmt::format("id {}", id));
      } catch (const LinkError& e) {
        bad.push_back(fmt::format("id {}: {}", id, e.what()));
      }
    }
    check("params_restored", bad.empty(),
          bad.empty() ? fmt::format("{} parameter{} set back and read back", touched_.size(), touched_.size() == 1 ? "" : "s")
                      : "not restored: " + join(bad, ", "));
    touched_.clear();
  }

  // ------------------------------------------------------------ duplicates
  void duplicate() {
    // PONG carries the uptime: a re-executed PING would answer a later one.
    p::Ping ping;
    ping.nonce = nonce();
    const uint8_t seq = pr_.next_seq();
    const auto bytes = Probe::wire(ping, seq);
    const Frame a = pr_.exchange(uint8_t(p::MsgType::Ping), seq, bytes);
    std::this_thread::sleep_for(Ms(30));
    const Frame b = pr_.exchange(uint8_t(p::MsgType::Ping), seq, bytes, 1);
    p::Pong pa, pb;
    const bool ok = as(a, pa) && as(b, pb) && a.header.seq == b.header.seq && a.header.flags == b.header.flags &&
                    a.payload == b.payload;
    check("duplicate_request", ok,
          ok ? fmt::format("PING seq {} sent twice 30 ms apart: identical PONG (uptime {} ms), not executed again", seq,
                           pa.uptime_ms)
             : fmt::format("PING seq {} sent twice: {} uptime {} then {} uptime {}", seq, describe(a), pa.uptime_ms,
                           describe(b), pb.uptime_ms));
  }

  // ---------------------------------------------------- malformed frames
  // No reply to `bytes`; the next PING is answered; a STATUS counter moved.
  void dropped(const std::string& name, const std::vector<uint8_t>& bytes, const std::string& what,
               uint32_t p::Status::*counter, const char* counter_name) {
    const auto before = status();
    const auto reply = pr_.expect_silence(bytes, std::max(Ms(300), pr_.timeout()));
    p::Ping ping;
    ping.nonce = nonce();
    const Frame f = pr_.request(ping);
    p::Pong pong;
    const bool answered = as(f, pong) && pong.nonce == ping.nonce;
    const auto after = status();
    const bool counted = before && after && (*after).*counter > (*before).*counter;
    std::string detail = what + (reply ? ": answered by " + *reply : ": no reply") +
                         (answered ? ", next PING answered" : ", next PING answered by " + describe(f));
    if (before && after)
      detail += fmt::format(", {} {} -> {}", counter_name, (*before).*counter, (*after).*counter);
    check(name, !reply && answered && counted, detail);
  }

  void malformed() {
    std::vector<uint8_t> garbage = {0x00};
    for (const char* s = "\x07garbage!\x13\x37\xff\xfe"; *s; ++s) garbage.push_back(uint8_t(*s));
    garbage.push_back(p::kDelimiter);
    dropped("garbage", garbage, fmt::format("{} bytes of garbage", garbage.size()), &p::Status::frame_errors,
            "frame_errors");

    {
      p::Ping ping;
      ping.nonce = nonce();
      uint8_t payload[4];
      std::memcpy(payload, &ping.nonce, 4);
      p::Header h;
      h.type = uint8_t(p::MsgType::Ping);
      h.seq = pr_.next_seq();
      uint8_t buf[p::kWireBufferSize];
      const uint8_t wrong_seed = uint8_t(p::find_rule(h.type)->crc_extra ^ 0x5A);
      const size_t n = p::encode_frame_raw(h, payload, 4, wrong_seed, buf, sizeof buf);
      dropped("bad_crc", {buf, buf + n}, "PING with a bad CRC", &p::Status::crc_errors, "crc_errors");
    }

    // Section 5: a type outside the catalogue is dropped as unknown_type
    // (its CRC seed is unknown), so no reply at all, not NACK unsupported.
    {
      const uint8_t type = 0x3E;
      uint8_t payload[4] = {1, 2, 3, 4};
      p::Header h;
      h.type = type;
      h.seq = pr_.next_seq();
      uint8_t buf[p::kWireBufferSize];
      const size_t n = p::encode_frame_raw(h, payload, 4, 0x00, buf, sizeof buf);
      dropped("unknown_type", {buf, buf + n}, "request type 0x3e (not in the catalogue; section 5 drops it)",
              &p::Status::frame_errors, "frame_errors");
    }
  }

  // ----------------------------------------------------------- run control
  static bool acked(const Frame& f, p::MsgType request) {
    p::Ack a;
    return as(f, a) && a.request_type == uint8_t(request);
  }

  void run_control() {
    const uint16_t decimation = uint16_t(std::max<uint32_t>(1, info_.loop_rate_hz / 200));
    p::TelemetryConfig tc;
    tc.mask = p::telemetry_field::kStep;
    tc.decimation = decimation;
    const Frame cfg = pr_.request(tc);
    if (!acked(cfg, p::MsgType::TelemetryConfig)) {
      check("run_start", false, "TELEMETRY_CONFIG step/" + std::to_string(decimation) + " answered by " + describe(cfg));
      return;
    }
    p::RunStart start;
    start.run_id = 0xC0F00000u | uint32_t(rng_() & 0xFFFFu);
    pr_.record_telemetry(true);
    const Frame sf = pr_.request(start);
    const bool started = acked(sf, p::MsgType::RunStart);
    check("run_start", started, fmt::format("RUN_START run_id {}: {}", start.run_id, describe(sf)));
    std::string seen;
    if (started) {
      // Half a second of run; STATUS_GET meanwhile keeps the link watchdog fed.
      const auto until = Clock::now() + Ms(600);
      std::optional<p::Status> st;
      while (Clock::now() < until) {
        std::this_thread::sleep_for(Ms(100));
        st = status();
      }
      if (st) seen = fmt::format(", STATUS run_id {} state {} step {}", st->run_id, st->run_state, st->step);
    }
    const Frame stop = pr_.request(p::RunStop{});
    pr_.record_telemetry(false);
    check("run_stop", acked(stop, p::MsgType::RunStop), "RUN_STOP: " + describe(stop));
    if (started) {
      const auto t = pr_.telemetry();
      std::string gaps;
      for (size_t i = 1; i < t.size(); ++i) {
        if (uint16_t(t[i].tseq - t[i - 1].tseq) != 1 && gaps.size() < 80)
          gaps += fmt::format(" {}->{}", t[i - 1].tseq, t[i].tseq);
      }
      const bool ok = t.size() >= 3 && gaps.empty();
      check("telemetry", ok,
            t.empty() ? "no TELEMETRY between RUN_START and RUN_STOP"
                      : fmt::format("{} frames (decimation {}), tseq {}..{}, step {}..{}{}{}", t.size(), decimation,
                                    t.front().tseq, t.back().tseq, t.front().step, t.back().step,
                                    gaps.empty() ? ", consecutive" : ", gaps:" + gaps, seen));
    } else {
      check("telemetry", false, "no run started");
    }
    // Back to the mask in force before, every control step (the firmware's
    // default decimation; the live console sets its own on connect).
    p::TelemetryConfig back;
    back.mask = telemetry_mask_;
    back.decimation = 1;
    pr_.request(back);
  }

  // -------------------------------------------------------------- transfers
  std::vector<uint8_t> small_table() const {
    const uint32_t count = 16;
    std::vector<uint8_t> o(8 + 4u * info_.n * count, 0);
    o[0] = 1;
    o[1] = info_.n;
    std::memcpy(&o[4], &count, 4);
    for (uint32_t k = 0; k < count * info_.n; ++k) {
      const float x = 0.01f * float(k % 7);
      std::memcpy(&o[8 + 4 * k], &x, 4);
    }
    return o;
  }

  std::optional<p::XferAck> chunk(const std::vector<uint8_t>& obj, uint32_t offset, uint32_t size, std::string& err) {
    p::XferChunk c;
    c.kind = uint8_t(p::XferKind::RefTable);
    c.offset = offset;
    c.size = uint8_t(std::min<size_t>(size, obj.size() - offset));
    std::memcpy(c.data, obj.data() + offset, c.size);
    const Frame f = pr_.request(c);
    p::XferAck a;
    if (!as(f, a)) {
      err = fmt::format("CHUNK at {}: {}", offset, describe(f));
      return std::nullopt;
    }
    return a;
  }

  // BEGIN (restart), then every chunk from next_offset; returns the COMMIT
  // reply, or nothing with `err` set.
  std::optional<Frame> upload(const std::vector<uint8_t>& obj, uint32_t crc, bool skip_one, std::string& err,
                              std::string& log) {
    const uint32_t kChunk = 32;
    p::XferBegin b;
    b.kind = uint8_t(p::XferKind::RefTable);
    b.options = p::xfer_options::kRestart;
    b.total_size = uint32_t(obj.size());
    b.crc32 = crc;
    const Frame bf = pr_.request(b);
    p::XferAck a;
    if (!as(bf, a) || a.next_offset != 0) {
      err = "XFER_BEGIN: " + describe(bf) + (as(bf, a) ? fmt::format(" next_offset {}", a.next_offset) : "");
      return std::nullopt;
    }
    uint32_t next = 0;
    if (skip_one) {
      auto r = chunk(obj, 0, kChunk, err);
      if (!r) return std::nullopt;
      // Chunk 1 "lost": chunk 2 must be ignored, next_offset stays at 32.
      auto s = chunk(obj, 2 * kChunk, kChunk, err);
      if (!s) return std::nullopt;
      log += fmt::format("chunk at {} skipped, chunk at {} answered next_offset {}", kChunk, 2 * kChunk, s->next_offset);
      if (s->next_offset != kChunk) {
        err = log + fmt::format(" (expected {})", kChunk);
        return std::nullopt;
      }
      next = s->next_offset;
    }
    int guard = 0;
    while (next < obj.size()) {
      if (++guard > 1000) {
        err = "XFER_ACK next_offset does not advance";
        return std::nullopt;
      }
      auto r = chunk(obj, next, kChunk, err);
      if (!r) return std::nullopt;
      next = r->next_offset;
    }
    p::XferCommit c;
    c.kind = uint8_t(p::XferKind::RefTable);
    return pr_.request(c);
  }

  void transfers() {
    if (!(info_.capabilities & p::capability::kXferRefTable)) {
      check("xfer_heal", false, "INFO lacks the XFER_REF_TABLE capability");
      return;
    }
    const std::vector<uint8_t> obj = small_table();
    const uint32_t crc = nlsoft::crc32(obj.data(), obj.size());
    {
      std::string err, log;
      const auto commit = upload(obj, crc, true, err, log);
      if (!commit)
        check("xfer_heal", false, err);
      else
        check("xfer_heal", acked(*commit, p::MsgType::XferCommit),
              fmt::format("{}-byte table (kind 1), {}; resent from there, COMMIT: {}", obj.size(), log, describe(*commit)));
    }
    {
      std::string err, log;
      const auto commit = upload(obj, crc ^ 0x1u, false, err, log);
      p::Nack n;
      if (!commit)
        check("xfer_bad_checksum", false, err);
      else
        check("xfer_bad_checksum", as(*commit, n) && n.status == uint8_t(p::StatusCode::BadChecksum),
              fmt::format("table announced with a wrong CRC-32, COMMIT: {}", describe(*commit)));
    }
  }

  Probe& pr_;
  bool json_;
  std::vector<CheckResult> results_;
  p::Info info_;
  std::vector<p::ParamDesc> descs_;
  std::map<uint16_t, p::ParamValue> original_;
  std::set<uint16_t> touched_;
  uint8_t telemetry_mask_ = p::telemetry_field::kAll;
  std::mt19937 rng_{std::random_device{}()};
};

int run_conformance(const ConformanceArgs& a) {
  if (a.port.empty() == a.sim.empty())
    throw CliError("give a serial port (nlsoft-console conformance /dev/ttyACM0) or --sim PLATFORM, not both");
  SimLauncher sim;
  std::string port = a.port;
  if (!a.sim.empty()) port = sim.start(a.sim);
  Probe probe{Ms(a.timeout_ms)};
  Suite suite(probe, a.json);
  std::string error;
  try {
    probe.open(port, a.baud);
    suite.run(std::chrono::seconds(a.sim.empty() ? 10 : 3));
  } catch (const LinkError& e) {
    error = e.what();
  }
  int passed = 0, failed = 0;
  for (const auto& r : suite.results()) (r.pass ? passed : failed)++;
  if (a.json) {
    std::string o = "{\"port\":\"" + json_escape(port) + "\",\"checks\":[";
    for (size_t i = 0; i < suite.results().size(); ++i) {
      const auto& r = suite.results()[i];
      o += fmt::format("{}{{\"name\":\"{}\",\"pass\":{},\"detail\":\"{}\"}}", i ? "," : "", json_escape(r.name),
                       r.pass ? "true" : "false", json_escape(r.detail));
    }
    o += fmt::format("],\"passed\":{},\"failed\":{},\"link_error\":", passed, failed);
    o += error.empty() ? "null" : "\"" + json_escape(error) + "\"";
    std::printf("%s}\n", o.c_str());
  } else {
    if (!error.empty()) std::printf("link error: %s\n", error.c_str());
    std::printf("%d passed, %d failed\n", passed, failed);
  }
  std::fflush(stdout);
  if (!error.empty()) return 2;
  return failed ? 1 : 0;
}

}  // namespace

void add_conformance_command(CLI::App& app) {
  auto a = std::make_shared<ConformanceArgs>();
  CLI::App* c = app.add_subcommand(
      "conformance", "Run the protocol conformance suite (PROTOCOL.md) against a board or the simulator");
  c->add_option("PORT", a->port, "Serial device of the board, e.g. /dev/ttyACM0");
  c->add_option("--sim", a->sim, "Start nlsoft-firmware-sim for this platform and test it")
      ->check(CLI::IsMember({"msd", "hasel", "tendon"}));
  c->add_option("--baud", a->baud, "Baud rate (default 115200)")->check(CLI::Range(50u, 20000000u));
  c->add_option("--timeout", a->timeout_ms, "Reply timeout per try, ms (3 retries follow)")->check(CLI::Range(10, 60000));
  c->add_flag("--json", a->json, "One JSON object instead of PASS/FAIL lines");
  c->footer(
      "Checks: handshake, PING, STATUS_GET, PARAM_LIST/GET, PARAM_SET refusals (out of range, NaN,\n"
      "wrong size) and a valid set, duplicate requests, garbage, bad CRC and unknown types dropped,\n"
      "RUN_START/RUN_STOP with telemetry, a reference-table transfer that heals a lost chunk and one\n"
      "with a wrong CRC-32, replies' seq and REPLY flag. Parameters it changes are set back.\n"
      "Note: it commits a small reference table (kind 1) and leaves telemetry at decimation 1.\n"
      "Prints `PASS|FAIL name: detail` per check and `N passed, M failed`;\n"
      "exit 0 when all passed, 1 when one failed, 2 on a link error.\n"
      "Examples:\n"
      "  nlsoft-console conformance --sim hasel\n"
      "  nlsoft-console conformance /dev/ttyACM0 --baud 1000000 --json\n");
  c->callback([a] { throw CliExit{run_conformance(*a)}; });
}

}  // namespace nlsoft::console
