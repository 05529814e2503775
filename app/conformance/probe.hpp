#pragma once
// The wire end of the conformance suite: the console's own Session, used
// through its raw exchange so a check can choose sequence numbers, damage
// frames, write them a byte at a time or back to back. Everything the
// firmware sends besides the awaited reply is kept for the checks to judge:
// every reply (a reply to nothing we sent is a fault), telemetry, STATUS and
// LOG.
#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "app/link/link_error.hpp"
#include "app/link/session.hpp"
#include "protocol/encoder.hpp"
#include "protocol/messages.hpp"

namespace nlsoft::console::conformance {

namespace p = nlsoft::protocol;
using Ms = std::chrono::milliseconds;

// A reply as it arrived.
struct Frame {
  uint8_t type = 0;
  uint8_t seq = 0;
  std::vector<uint8_t> payload;
};

template <class M>
bool as(const Frame& f, M& m) {
  return f.type == uint8_t(M::kType) && p::unpack(f.payload.data(), f.payload.size(), m) == p::StatusCode::Ok;
}

// INFO_EX, or a 1.0 firmware's INFO (session.hpp's unpack_info).
bool as_info(const Frame& f, p::InfoEx& out);

// "PONG", "NACK: PARAM_SET refused: out of range (values[0])".
std::string describe(const Frame& f);
bool acked(const Frame& f, p::MsgType request);
// NACK of `status` naming (field, element); `got` describes what came.
bool nacked(const Frame& f, p::StatusCode status, uint8_t field, uint8_t element);

struct TelemetrySample {
  uint16_t tseq;
  uint32_t step;
  // Protocol 1.6: the width of the SENSOR_SAMPLE of this step that came
  // right before it; -1: none did.
  int sensors_w = -1;
};

class Probe {
 public:
  explicit Probe(Ms timeout);
  ~Probe();

  void open(const std::string& path, unsigned baud);
  Ms timeout() const { return timeout_; }
  LinkStats stats() const { return session_.stats(); }
  // Why no INFO came since `before` (a stats() snapshot), in the console's words.
  std::string no_info_words(const LinkStats& before, std::chrono::steady_clock::duration waited) const {
    return session_.no_info_words(before, waited, baud_);
  }
  uint8_t next_seq();

  static std::vector<uint8_t> wire(uint8_t type, uint8_t seq, const uint8_t* payload, size_t len, uint8_t flags = 0);
  template <class Req>
  static std::vector<uint8_t> wire(const Req& req, uint8_t seq, uint8_t flags = 0) {
    uint8_t payload[p::kMaxPayload];
    payload[0] = 0;
    size_t len = 0;
    if (p::pack(req, payload, sizeof payload, len) != p::StatusCode::Ok)
      throw LinkError(std::string("cannot encode ") + p::message_name(uint8_t(Req::kType)));
    return wire(uint8_t(Req::kType), seq, payload, len, flags);
  }

  // A request with a fresh seq; the frame that answers it. Throws LinkError
  // when none came after `tries` identical copies. Each retry waits twice as
  // long as the try before (250, 500, 1000, 2000 ms at --timeout 250): a
  // loaded host can leave the firmware process, or the emulator, unscheduled
  // for a second or two, and a conformant device is not to fail for that.
  // How often it took a retry is reported (late()), not hidden.
  template <class Req>
  Frame request(const Req& req, int tries = 4) {
    const uint8_t seq = next_seq();
    return exchange(uint8_t(Req::kType), seq, wire(req, seq), tries);
  }
  Frame exchange(uint8_t type, uint8_t seq, const std::vector<uint8_t>& bytes, int tries = 4,
                 size_t write_chunk = 0, Ms chunk_gap = Ms(0));
  // As exchange, but no reply is an answer too.
  std::optional<Frame> try_exchange(uint8_t type, uint8_t seq, const std::vector<uint8_t>& bytes, Ms wait);

  // Writes bytes that are not one awaited request (frames that must get no
  // reply, requests written back to back), then `fence` (a PING) as a
  // request: the firmware serves
  // its port in order, so whatever it answers the bytes with arrives before
  // the PONG, and no quiet window need pass. Returns the replies heard
  // before the fence's answer (its retries' copies left out); `answer` is
  // that answer. Throws LinkError as request() does.
  std::vector<Frame> send_fenced(const std::vector<uint8_t>& bytes, const p::Ping& fence, Frame& answer);
  // The bytes at the open baud's rate (10 bits a byte), as a line brings them.
  void write_at_line_rate(const std::vector<uint8_t>& bytes);

  void record_telemetry(bool on);
  std::vector<TelemetrySample> telemetry();
  // SENSOR_SAMPLEs recorded that no TELEMETRY of their step followed.
  unsigned stray_sensor_samples() const;
  // IDENT_SAMPLE frames (protocol 1.3) since the last take, kept always:
  // an identification run's samples are few enough (the checks' runs are short).
  std::vector<p::IdentSample> take_ident_samples();
  // STATUS frames in arrival order since the last call (replies included).
  std::vector<p::Status> take_statuses();
  std::vector<std::string> take_logs();

  // Requests answered only after a retry, and the longest wait for one:
  // which request it was says where in the conversation the host stalled.
  struct Late {
    unsigned requests = 0;
    Ms longest{0};
    std::string longest_request;  // "PARAM_GET seq 21"
  };
  Late late() const;

  // Request types that got an answer other than NACK.
  std::set<uint8_t> answered() const;
  // What the firmware has sent so far, by type: replies and unsolicited.
  std::set<uint8_t> types_seen() const;
  unsigned replies() const;
  // Replies whose seq none of our recent requests carried.
  unsigned foreign_replies() const;
  std::string first_foreign() const;

 private:
  Ms timeout_;
  unsigned baud_ = 0;
  Session session_;
  mutable std::mutex mu_;
  std::deque<uint8_t> recent_seqs_;  // a reply to none of these answers nothing we sent lately
  void note_sent(uint8_t seq);
  std::string heard_while_waiting(const LinkStats& before) const;
  std::set<uint8_t> types_seen_;
  std::set<uint8_t> answered_;
  Late late_;
  std::optional<Frame> done(uint8_t type, const std::optional<Reply>& r);
  std::vector<Frame> heard_;  // replies collected by send_fenced
  void listen();
  std::vector<Frame> stop_listening();
  // Seqs whose reply was already taken, and a snapshot of them while
  // listening: a late copy of such a reply (the answer to a retry, on a slow
  // host) is not an answer to the bytes being listened after.
  std::deque<uint8_t> taken_seqs_;
  std::set<uint8_t> listen_ignores_;
  bool listening_ = false;
  unsigned replies_ = 0, foreign_ = 0;
  std::string first_foreign_;
  // Copies written and replies heard, per seq. A check that sends a seq
  // again (a duplicate, the same seq with another body) must not take a late
  // answer to an earlier copy, retried on a slow host, for the firmware's
  // answer to the new one: exchange() first waits for those (settle()).
  std::array<unsigned, 256> copies_{}, answers_{};
  std::condition_variable answered_cv_;
  void settle(uint8_t seq);
  // Writes req once settled, counts the copies written; `before` is the stats as it began.
  std::optional<Frame> send(const RawRequest& req, LinkStats& before);
  bool recording_ = false;
  std::vector<TelemetrySample> telemetry_;
  std::optional<p::SensorSample> sensors_;  // the latest, until a TELEMETRY takes it
  unsigned stray_sensors_ = 0;
  std::vector<p::IdentSample> ident_;
  std::vector<p::Status> statuses_;
  std::vector<std::string> logs_;
};

}  // namespace nlsoft::console::conformance
