// Framing, receiving and duplicates (PROTOCOL.md 2, 5, 10): damaged frames
// are dropped unanswered and counted, the next frame is served; frames may
// arrive a byte at a time or back to back; a retransmission gets the stored
// reply and a reused seq with another request is executed.
#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <thread>

#include "app/conformance/suite.hpp"
#include "protocol/cobs.hpp"

namespace nlsoft::console::conformance {

namespace {

// No reply to `bytes`; the next PING is answered; a STATUS counter moved by
// at least `at_least`.
void dropped(Suite& s, const std::string& name, const std::vector<uint8_t>& bytes, const std::string& what,
             uint32_t p::Status::*counter, const char* counter_name, uint32_t at_least = 1) {
  const auto before = s.status();
  p::Ping ping;
  ping.nonce = s.random();
  Frame f;
  const auto heard = s.pr.send_fenced(bytes, ping, f);
  p::Pong pong;
  const bool answered = as(f, pong) && pong.nonce == ping.nonce;
  const auto after = s.status();
  const bool counted = before && after && (*after).*counter - (*before).*counter >= at_least;
  std::string detail = what + (heard.empty() ? ": no reply" : ": answered by " + describe(heard.front())) +
                       (answered ? ", next PING answered" : ", next PING answered by " + describe(f));
  if (before && after) detail += fmt::format(", {} {} -> {}", counter_name, (*before).*counter, (*after).*counter);
  s.check(name, heard.empty() && answered && counted, detail);
}

std::vector<uint8_t> raw_of(const std::vector<uint8_t>& wire) {
  std::vector<uint8_t> raw(p::kMaxRawFrame + 8);
  const p::CobsDecodeResult r = p::cobs_decode(wire.data(), wire.size() - 1, raw.data(), raw.size());
  raw.resize(r.size);
  return raw;
}

std::vector<uint8_t> cobs_wire(const std::vector<uint8_t>& raw) {
  std::vector<uint8_t> out(p::cobs_max_encoded_size(raw.size()) + 1);
  out.resize(p::cobs_encode(raw.data(), raw.size(), out.data(), out.size()));
  out.push_back(p::kDelimiter);
  return out;
}

// Back-to-back delimiters are idle, not errors.
void check_idle_delimiters(Suite& s) {
  const auto before = s.status();
  p::Ping ping;
  ping.nonce = s.random();
  Frame f;
  const auto heard = s.pr.send_fenced(std::vector<uint8_t>(64, p::kDelimiter), ping, f);
  const auto after = s.status();
  const bool same = before && after && before->frame_errors == after->frame_errors &&
                    before->crc_errors == after->crc_errors;
  s.check("idle_delimiters", heard.empty() && same,
          fmt::format("64 zero bytes: {}, error counters {}", heard.empty() ? "no reply" : "a reply",
                      same ? "unchanged" : "moved"));
}

// Every single-bit flip of a PARAM_SET frame: each dropped (the CRC or
// an earlier check catches it), none answered, none applied.
void check_bit_flips(Suite& s) {
  const p::ParamDesc* q = s.param("Q");
  if (!q) q = s.descs.empty() ? nullptr : &s.descs.front();
  if (!q || q->type != uint8_t(p::ParamType::F32)) {
    s.check("bit_flips", true, "no f32 parameter to try");
    return;
  }
  const auto current = s.get(q->id);
  if (!current) throw LinkError(std::string("PARAM_GET ") + q->name + " refused");
  const p::ParamValue orig = *current;
  p::ParamSet set;
  set.id = q->id;
  set.count = orig.count;
  for (uint8_t i = 0; i < set.count; ++i)
    set.set_f32(i, std::isfinite(q->max) && q->max > 0 ? q->max : 1.0f);  // never the value in force
  const uint8_t seq = s.pr.next_seq();
  const std::vector<uint8_t> raw = raw_of(Probe::wire(set, seq));
  std::vector<uint8_t> all;
  size_t frames = 0;
  for (size_t bit = 0; bit < raw.size() * 8; ++bit) {
    std::vector<uint8_t> r = raw;
    r[bit / 8] ^= uint8_t(1u << (bit % 8));
    const auto w = cobs_wire(r);
    all.insert(all.end(), w.begin(), w.end());
    ++frames;
  }
  const auto before = s.status();
  p::Ping ping;
  ping.nonce = s.random();
  Frame f;
  const auto heard = s.pr.send_fenced(all, ping, f);
  const auto after = s.status();
  const auto now = s.get(q->id);
  const bool unchanged = now && now->count == orig.count && std::memcmp(now->values, orig.values, 4u * orig.count) == 0;
  if (!unchanged) s.touched.insert(q->id);
  const uint32_t errors = before && after ? (after->crc_errors + after->frame_errors) -
                                                (before->crc_errors + before->frame_errors)
                                          : 0;
  s.check("bit_flips", heard.empty() && unchanged && errors >= frames,
          fmt::format("{} frames, each PARAM_SET {} with one bit flipped: {}, {} counted as errors, value {}", frames,
                      q->name, heard.empty() ? "no reply" : "answered by " + describe(heard.front()), errors,
                      unchanged ? "unchanged" : "CHANGED"));
}

void damaged(Suite& s) {
  std::vector<uint8_t> garbage = {0x00};
  for (const char* c = "\x07garbage!\x13\x37\xff\xfe"; *c; ++c) garbage.push_back(uint8_t(*c));
  garbage.push_back(p::kDelimiter);
  dropped(s, "garbage", garbage, fmt::format("{} bytes of garbage", garbage.size()), &p::Status::frame_errors,
          "frame_errors");
  {
    // A burst of random bytes, with delimiters where they fall.
    std::vector<uint8_t> burst(1024);
    for (auto& b : burst) b = uint8_t(s.random());
    burst.push_back(p::kDelimiter);
    dropped(s, "garbage_burst", burst, "1 KiB of random bytes", &p::Status::frame_errors, "frame_errors");
  }
  check_idle_delimiters(s);
  {
    p::Ping ping;
    ping.nonce = s.random();
    uint8_t payload[4];
    std::memcpy(payload, &ping.nonce, 4);
    p::Header h;
    h.type = uint8_t(p::MsgType::Ping);
    h.seq = s.pr.next_seq();
    uint8_t buf[p::kWireBufferSize];
    const uint8_t wrong_seed = uint8_t(p::find_rule(h.type)->crc_extra ^ 0x5A);
    const size_t n = p::encode_frame_raw(h, payload, 4, wrong_seed, buf, sizeof buf);
    dropped(s, "bad_crc", {buf, buf + n}, "PING with a bad CRC", &p::Status::crc_errors, "crc_errors");
  }
  {
    // Section 5: a type outside the catalogue is dropped as unknown_type
    // (its seed is unknown), so no reply at all, not NACK unsupported.
    uint8_t payload[4] = {1, 2, 3, 4};
    p::Header h;
    h.type = 0x3E;
    h.seq = s.pr.next_seq();
    uint8_t buf[p::kWireBufferSize];
    const size_t n = p::encode_frame_raw(h, payload, 4, 0x00, buf, sizeof buf);
    dropped(s, "unknown_type", {buf, buf + n}, "request type 0x3e (not in the catalogue)", &p::Status::frame_errors,
            "frame_errors");
  }
  {
    // PING with a 3-byte payload: the type's length rule (bad_length).
    const uint8_t payload[3] = {1, 2, 3};
    p::Header h;
    h.type = uint8_t(p::MsgType::Ping);
    h.seq = s.pr.next_seq();
    uint8_t buf[p::kWireBufferSize];
    const size_t n = p::encode_frame_raw(h, payload, 3, p::crc_extra(h.type), buf, sizeof buf);
    dropped(s, "bad_length", {buf, buf + n}, "PING with 3 payload bytes", &p::Status::frame_errors, "frame_errors");
  }
  check_bit_flips(s);
}

void byte_at_a_time(Suite& s) {
  p::Ping ping;
  ping.nonce = s.random();
  const uint8_t seq = s.pr.next_seq();
  const Frame f = s.pr.exchange(uint8_t(p::MsgType::Ping), seq, Probe::wire(ping, seq), 4, 1, Ms(2));
  p::Pong pong;
  s.check("byte_at_a_time", as(f, pong) && pong.nonce == ping.nonce,
          "PING written one byte per write, 2 ms apart: " + describe(f));
}

void duplicates(Suite& s) {
  // PONG carries the uptime: a re-executed PING would answer a later one.
  // Each exchange may be retried: a retry is one more copy of the same
  // request, answered from the stored reply, so it proves the same thing,
  // and one try lost to an emulator the host did not schedule for the
  // timeout is no link error.
  p::Ping ping;
  ping.nonce = s.random();
  const uint8_t seq = s.pr.next_seq();
  const auto bytes = Probe::wire(ping, seq);
  const Frame a = s.pr.exchange(uint8_t(p::MsgType::Ping), seq, bytes);
  std::this_thread::sleep_for(Ms(30));
  const Frame b = s.pr.exchange(uint8_t(p::MsgType::Ping), seq, bytes);
  p::Pong pa, pb;
  const bool ok = as(a, pa) && as(b, pb) && a.payload == b.payload;
  s.check("duplicate_request", ok,
          ok ? fmt::format("PING seq {} sent twice 30 ms apart: identical PONG (uptime {} ms), not executed again", seq,
                           pa.uptime_ms)
             : fmt::format("PING seq {} sent twice: {} uptime {} then {} uptime {}", seq, describe(a), pa.uptime_ms,
                           describe(b), pb.uptime_ms));

  // The same seq with another body is a new request (a restarted console).
  p::Ping other;
  other.nonce = ping.nonce ^ 0xA5A5A5A5u;
  const Frame c = s.pr.exchange(uint8_t(p::MsgType::Ping), seq, Probe::wire(other, seq));
  p::Pong pc;
  const bool executed = as(c, pc) && pc.nonce == other.nonce;
  s.check("reused_seq_executed", executed,
          fmt::format("PING seq {} again with nonce 0x{:08x}: {} nonce 0x{:08x}", seq, other.nonce, describe(c),
                      pc.nonce));

  // A replay of an older request, after another one, is executed anew: the
  // firmware remembers only the last request.
  p::Ping between;
  between.nonce = s.random();
  s.pr.request(between);
  std::this_thread::sleep_for(Ms(20));
  const Frame d = s.pr.exchange(uint8_t(p::MsgType::Ping), seq, bytes);
  p::Pong pd;
  const bool again = as(d, pd) && pd.nonce == ping.nonce && pd.uptime_ms >= pa.uptime_ms;
  s.check("replayed_seq", again,
          fmt::format("PING seq {} replayed after another request: {} nonce 0x{:08x} uptime {} ms (first {} ms)", seq,
                      describe(d), pd.nonce, pd.uptime_ms, pa.uptime_ms));
}

void pipelined(Suite& s) {
  // Requests written back to back are each answered, in order.
  std::vector<uint8_t> bytes;
  std::vector<uint8_t> seqs;
  std::vector<uint32_t> nonces;
  for (int i = 0; i < 3; ++i) {
    p::Ping ping;
    ping.nonce = s.random();
    const uint8_t seq = s.pr.next_seq();
    const auto w = Probe::wire(ping, seq);
    bytes.insert(bytes.end(), w.begin(), w.end());
    seqs.push_back(seq);
    nonces.push_back(ping.nonce);
  }
  const uint8_t st_seq = s.pr.next_seq();
  const auto w = Probe::wire(p::StatusGet{}, st_seq);
  bytes.insert(bytes.end(), w.begin(), w.end());
  seqs.push_back(st_seq);
  p::Ping fence;
  fence.nonce = s.random();
  Frame f;
  const auto heard = s.pr.send_fenced(bytes, fence, f);
  std::vector<std::string> got;
  bool ok = heard.size() == seqs.size();
  for (size_t i = 0; i < heard.size(); ++i) {
    got.push_back(fmt::format("{} seq {}", describe(heard[i]), heard[i].seq));
    if (i >= seqs.size() || heard[i].seq != seqs[i]) ok = false;
    p::Pong pong;
    if (i < 3 && !(as(heard[i], pong) && pong.nonce == nonces[i])) ok = false;
    p::Status st;
    if (i == 3 && !as(heard[i], st)) ok = false;
  }
  s.check("pipelined", ok,
          fmt::format("3 PINGs and a STATUS_GET back to back: {}", got.empty() ? "no reply" : join(got, ", ")));
}

}  // namespace

void check_framing(Suite& s) {
  s.group("framing");
  damaged(s);
  byte_at_a_time(s);
  duplicates(s);
  pipelined(s);
}

}  // namespace nlsoft::console::conformance
