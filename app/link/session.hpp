#pragma once
// Request/reply over the serial link (PROTOCOL.md sections 9-10): one
// outstanding request at a time, matched to its reply by sequence number on
// the single reader, retransmitted unchanged (same seq) on timeout a bounded
// number of times. A reply that arrives as a timeout fires is decided under
// one mutex, so it is either taken or the retry goes out, never both lost.
// Unsolicited TELEMETRY, STATUS and LOG go to handlers; link loss and
// recovery go to an event handler on a supervisor thread, which is where a
// re-handshake may block. A port is reopened by its name, and a name can
// lead to another device afterwards (another board on /dev/ttyACM0, another
// program's pty on a freed /dev/pts/N): once the device has sent INFO, the
// link only counts as back when the peer sends the same identity again.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <type_traits>
#include <thread>
#include <vector>

#include "app/link/link_error.hpp"
#include "app/link/link_stats.hpp"
#include "app/link/serial_link.hpp"
#include "protocol/decoder.hpp"
#include "protocol/messages.hpp"

namespace nlsoft::console {

struct SessionOptions {
  std::chrono::milliseconds timeout{250};          // per try
  std::chrono::milliseconds commit_timeout{1500};  // XFER_COMMIT validates a whole object; SETTINGS erases flash
  int tries = 4;                                   // first send + 3 retransmissions
  std::chrono::milliseconds silence_limit{3000};   // heartbeat is 1 s
  std::chrono::milliseconds reconnect_interval{300};
  // The firmware's link watchdog (1 s by default) puts the actuators in the
  // safe state when the console goes quiet during a run; a PING at this
  // interval whenever nothing else was sent keeps it fed. 0 disables.
  std::chrono::milliseconds keepalive{300};
};

// What came from the port while requests went unanswered, from two
// snapshots of the stats: the one diagnosis behind every "no reply" and "no
// INFO" message (the session's, the handshake's, the conformance suite's).
struct LineHeard {
  enum class Kind {
    Nothing,       // a silent line: no byte at all
    Noise,         // bytes, none of them a valid frame (another baud rate, another device)
    Echo,          // valid frames, every one a request as the console sends them (a loopback)
    OtherVersion,  // frames of another protocol version
    Frames,        // the firmware's frames, but no answer to the request
  };
  Kind kind = Kind::Nothing;
  uint64_t bytes = 0, frames = 0;
  uint8_t version = 0;  // OtherVersion: the version byte the peer speaks
};

// The fact in words, naming the port: "nothing arrived from /dev/pts/3",
// "600 bytes arrived from /dev/pts/3, none of them a valid frame (another
// baud rate, or not an nlsoft firmware?)", ... Empty for Frames.
std::string heard_words(const LineHeard& h, const std::string& port);

// "250 ms", "1.25 s": a wait as the messages give it.
std::string wait_words(std::chrono::steady_clock::duration d);

struct Reply {
  uint8_t type = 0;
  uint8_t seq = 0;
  uint8_t length = 0;
  uint8_t payload[protocol::kMaxPayload] = {};
};

struct LinkEvent {
  // Foreign: the port reopened but another device answers there.
  // Refused: a frame the firmware sent was dropped (dimensions other than
  // its INFO's, values not finite); said once per session and fault.
  enum class Kind { Down, Up, Silent, Resumed, Foreign, Refused };
  Kind kind;
  std::string detail;
};

const char* link_event_name(LinkEvent::Kind k);

// INFO_GET's answer from either protocol revision: INFO_EX (1.1) as is, INFO
// (1.0) with the fields it lacks at 0 (limits unknown, protocol_minor 0).
bool unpack_info(const Reply& r, protocol::InfoEx& out);

// One request exactly as the caller built it, for tools that must choose the
// bytes: a chosen seq (duplicates, replays), damaged frames, frames written
// a few bytes at a time.
struct RawRequest {
  std::vector<uint8_t> wire;  // what goes on the line, delimiter included
  uint8_t type = 0;           // the request it carries, to recognise the reply
  uint8_t seq = 0;
  int tries = 1;              // identical copies sent, each after a timeout
  std::chrono::milliseconds timeout{250};
  bool backoff = false;       // each retry waits twice as long as the try before
  size_t write_chunk = 0;     // > 0: written in pieces of this many bytes
  std::chrono::milliseconds chunk_gap{0};
};

class Session {
 public:
  using TelemetryHandler = std::function<void(const protocol::Telemetry&, uint32_t lost_before)>;
  // Protocol 1.3: an identification run's samples, counted with TELEMETRY's tseq.
  using IdentHandler = std::function<void(const protocol::IdentSample&, uint32_t lost_before)>;
  // Protocol 1.4: the health of the sensor channels at the step of the
  // sample frame before it (a rig with sensor chips).
  using HealthHandler = std::function<void(const protocol::SensorHealth&)>;
  // Protocol 1.6: a closed-loop step's sensors, before its TELEMETRY, its
  // width already checked against INFO's w.
  using SensorSampleHandler = std::function<void(const protocol::SensorSample&)>;
  using StatusHandler = std::function<void(const protocol::Status&)>;
  using LogHandler = std::function<void(const protocol::Log&)>;
  using EventHandler = std::function<void(const LinkEvent&)>;
  using ReplyHandler = std::function<void(const protocol::FrameView&)>;

  explicit Session(SessionOptions options = {});
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // Set before open(). Telemetry/status/log handlers run on the I/O thread
  // and must not block; the event handler runs on the supervisor thread.
  void on_telemetry(TelemetryHandler h) { telemetry_handler_ = std::move(h); }
  void on_ident_sample(IdentHandler h) { ident_handler_ = std::move(h); }
  void on_sensor_health(HealthHandler h) { health_handler_ = std::move(h); }
  void on_sensor_sample(SensorSampleHandler h) { sensor_sample_handler_ = std::move(h); }
  void on_status(StatusHandler h) { status_handler_ = std::move(h); }
  void on_log(LogHandler h) { log_handler_ = std::move(h); }
  void on_event(EventHandler h) { event_handler_ = std::move(h); }
  // Every frame with REPLY set, matched or not (I/O thread): a tool that
  // pipelines requests or checks for unwanted replies sees them all. It runs
  // before the reply can answer a request and before a request sent after it
  // can take a reply, under the session's reply lock: it must not call the
  // session.
  void on_any_reply(ReplyHandler h) { any_reply_handler_ = std::move(h); }

  void open(const std::string& path, unsigned baud);  // throws LinkError
  // After close() no handler runs for this link; link events it had not
  // delivered yet are dropped, never passed on after the next open().
  void close();

  // Sends a request and waits for its reply (any type). Throws LinkError
  // after the last try.
  Reply transact(uint8_t type, const uint8_t* payload, size_t length);

  // Typed request: returns the expected reply, throws NackError on NACK and
  // LinkError on anything else.
  // The raw exchange under the typed calls: sends req.wire (tries times,
  // unchanged) and returns the reply with req.seq that answers req.type, or
  // nothing when none came. Serialised with every other request.
  std::optional<Reply> exchange(const RawRequest& req);
  // Bytes that are not a request (garbage, pipelined frames); no reply is awaited.
  void write_raw(const std::vector<uint8_t>& bytes);
  // A fresh sequence number, as transact() would use next.
  uint8_t next_seq();

  template <class Rep, class Req>
  Rep call(const Req& req) {
    uint8_t payload[protocol::kMaxPayload];
    payload[0] = 0;
    size_t len = 0;
    if (protocol::pack(req, payload, sizeof payload, len) != protocol::StatusCode::Ok)
      throw LinkError(std::string("cannot encode ") + protocol::message_name(uint8_t(Req::kType)) +
                      ": a value does not fit the message");
    const Reply r = transact(uint8_t(Req::kType), payload, len);
    if (r.type == uint8_t(protocol::MsgType::Nack)) throw_nack(r);
    Rep out;
    if (!unpack_reply(r, out)) unexpected(r, uint8_t(Req::kType));
    return out;
  }

  LinkStats stats() const;
  // Bytes as they came from the port (the link's reader calls it): the
  // console's whole intake starts here, which is where the fuzzer feeds it.
  void on_bytes(const uint8_t* data, size_t len);
  // The identity an INFO reply gives (transact() takes it from the reply):
  // given directly where there is no request to answer, as in the fuzzer,
  // so the sample frames are checked against it.
  void take_identity(const protocol::Info& info) {
    std::lock_guard<std::mutex> lock(identity_mu_);
    identity_ = info;
    have_identity_ = true;
  }
  // SerialLink::take_longest_write_gap: how long the console went without
  // writing to the port since the last call.
  std::chrono::milliseconds take_longest_write_gap() { return link_.take_longest_write_gap(); }
  // What arrived since `before` (a stats() snapshot), for a request or a
  // handshake that got no answer.
  LineHeard heard_since(const LinkStats& before) const;
  // "no INFO from PORT in 3.0 s of asking: nothing arrived: is the firmware
  // running, at 115200 baud?": why a device never identified itself, from
  // what arrived since `before`. The console's handshake and the
  // conformance suite both say it.
  std::string no_info_words(const LinkStats& before, std::chrono::steady_clock::duration waited, unsigned baud) const;
  // The port is open and leads to the device identified before (if any).
  bool connected() const { return link_.is_up() && peer_.load() == Peer::Known; }
  // A copy: a reconnect to another port (a restarted simulator) renames it
  // on the worker while the screen reads it.
  std::string port() const {
    std::lock_guard<std::mutex> lock(port_mu_);
    return port_;
  }
  bool will_reopen() const { return link_.will_reopen(); }  // false: the port is gone for good (a hung-up pty)
  const SessionOptions& options() const { return options_; }
  // Protocol version byte of frames dropped as wrong_version, 0 if none.
  uint8_t foreign_version() const { return foreign_version_.load(); }

 private:
  uint32_t count_telemetry(uint16_t tseq);  // frames lost before this one; stats_mu_ taken
  template <class Rep>
  static bool unpack_reply(const Reply& r, Rep& out) {
    if constexpr (std::is_same_v<Rep, protocol::InfoEx>) {
      return unpack_info(r, out);
    } else if constexpr (std::is_same_v<Rep, protocol::Info>) {
      protocol::InfoEx ex;
      if (!unpack_info(r, ex)) return false;
      out = ex.info;
      return true;
    } else {
      return r.type == uint8_t(Rep::kType) && protocol::unpack(r.payload, r.length, out) == protocol::StatusCode::Ok;
    }
  }
  Reply transact_locked(uint8_t type, const uint8_t* payload, size_t length, bool identifying = false);
  std::optional<Reply> exchange_locked(const RawRequest& req, bool identifying, int& sent);
  void check_peer();
  void keepalive();
  void on_frame(const protocol::FrameView& f);
  // A sample frame the session will not pass on: counted, its tseq left
  // uncounted so the next frame shows it as lost, said once per fault.
  void refuse_sample(int fault, const std::string& words);
  void on_reply(const protocol::FrameView& f);
  void post_event(LinkEvent e);
  void supervise();
  [[noreturn]] void throw_nack(const Reply& r) const;
  [[noreturn]] void unexpected(const Reply& r, uint8_t request_type) const;

  SessionOptions options_;
  SerialLink link_;
  protocol::Decoder decoder_;  // I/O thread only

  IdentHandler ident_handler_;
  HealthHandler health_handler_;
  SensorSampleHandler sensor_sample_handler_;
  TelemetryHandler telemetry_handler_;
  StatusHandler status_handler_;
  LogHandler log_handler_;
  EventHandler event_handler_;
  ReplyHandler any_reply_handler_;

  // One request in flight (stop-and-wait).
  std::mutex request_mu_;
  std::mutex pending_mu_;
  std::condition_variable pending_cv_;
  bool pending_active_ = false;
  bool pending_done_ = false;
  bool pending_identifying_ = false;  // the INFO_GET of check_peer()
  uint8_t pending_seq_ = 0;
  uint8_t pending_type_ = 0;
  Reply pending_reply_;
  uint8_t next_seq_ = 0;  // random at start (PROTOCOL.md section 10)

  // Supervisor: events, silence detection, rates.
  std::thread supervisor_;
  std::mutex event_mu_;
  std::condition_variable event_cv_;
  std::vector<LinkEvent> events_;
  bool stopping_ = false;

  mutable std::mutex port_mu_;
  std::string port_;
  mutable std::mutex stats_mu_;
  LinkStats stats_;  // counters; rates filled by the supervisor
  bool have_tseq_ = false;
  uint16_t last_tseq_ = 0;
  bool have_last_status_ = false;
  protocol::Status last_status_{};
  uint32_t nominal_rate_hz_ = 0;
  std::atomic<int64_t> last_frame_ns_{0};
  std::atomic<int64_t> last_echo_ns_{0};  // when one of our own frames last came back
  std::atomic<int64_t> last_tx_ns_{0};
  uint32_t ping_nonce_ = 0;
  std::atomic<uint8_t> foreign_version_{0};
  uint8_t foreign_candidate_ = 0;  // I/O thread only: the last foreign version seen
  int foreign_streak_ = 0;         // and how many times running

  // Who answers at the port. Known: the device identified by its last INFO
  // (or nothing to compare with yet). Unchecked: the port was lost; whatever
  // it leads to now gets nothing but INFO_GET and its frames are dropped
  // until it sends the same identity. Foreign: it sent another one; it stays
  // refused until the port is lost again.
  enum class Peer : uint8_t { Known, Unchecked, Foreign };
  std::atomic<Peer> peer_{Peer::Known};  // changed under identity_mu_
  std::atomic<uint64_t> losses_{0};       // ports lost, so a late answer is not taken for the new peer
  mutable std::mutex identity_mu_;
  bool have_identity_ = false;
  protocol::Info identity_{};  // the last INFO of the known device
  bool said_refused_[3] = {};  // SampleFault: a refusal is said once a session
  std::string foreign_;        // why the peer is refused, in words

 public:
  // INFO's loop rate, shown when the firmware is idle.
  void set_nominal_rate(uint32_t hz) {
    std::lock_guard<std::mutex> lock(stats_mu_);
    nominal_rate_hz_ = hz;
  }
};

}  // namespace nlsoft::console
