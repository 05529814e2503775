#include "app/link/session.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "app/link/port_openers.hpp"
#include "app/link/sample_check.hpp"
#include "host/files/printable.hpp"
#include "app/link/session_words.hpp"
#include "app/link/steady_ns.hpp"
#include "protocol/catalog.hpp"
#include "protocol/encoder.hpp"

namespace nlsoft::console {

using host::printable_into;

namespace p = nlsoft::protocol;
using Clock = std::chrono::steady_clock;

namespace {

// ACK and NACK name the request they answer; the other replies by type
// (protocol/catalog.hpp, section 6's reply column).
bool answers(uint8_t request, const p::FrameView& f) {
  const uint8_t t = f.header.type;
  if (!p::answers(request, t)) return false;
  if (t == uint8_t(p::MsgType::Ack) || t == uint8_t(p::MsgType::Nack))
    return f.header.length >= 1 && f.payload[0] == request;
  return true;
}

}  // namespace

bool unpack_info(const Reply& r, p::InfoEx& out) {
  if (r.type == uint8_t(p::MsgType::InfoEx)) return p::unpack(r.payload, r.length, out) == p::StatusCode::Ok;
  if (r.type != uint8_t(p::MsgType::Info)) return false;
  out = p::InfoEx{};
  out.protocol_minor = 0;
  return p::unpack(r.payload, r.length, out.info) == p::StatusCode::Ok;
}

Session::Session(SessionOptions options) : options_(options) {
  link_.set_reconnect_interval(options_.reconnect_interval);
  // A console restarted within a few requests would otherwise reuse the
  // seq of its previous life's last request, and a firmware that still
  // remembers it could take the new request for a retransmission.
  next_seq_ = uint8_t(std::random_device{}());
}

Session::~Session() { close(); }

// TELEMETRY and IDENT_SAMPLE share one sequence: the frames missing
// between this one and the last are lost.
uint32_t Session::count_telemetry(uint16_t tseq) {
  std::lock_guard<std::mutex> lock(stats_mu_);
  ++stats_.telemetry_frames;
  const uint32_t lost = have_tseq_ ? uint16_t(tseq - last_tseq_ - 1) : 0;
  stats_.lost_telemetry += lost;
  have_tseq_ = true;
  last_tseq_ = tseq;
  return lost;
}

void Session::open(const std::string& path, unsigned baud) {
  SerialLink::Handlers h;
  h.on_bytes = [this](const uint8_t* d, size_t n) { on_bytes(d, n); };
  h.on_down = [this](const std::string& why) {
    decoder_.reset();
    {
      // Whatever the name leads to next must identify itself first.
      std::lock_guard<std::mutex> lock(identity_mu_);
      if (have_identity_) peer_ = Peer::Unchecked;
      ++losses_;
    }
    {
      std::lock_guard<std::mutex> lock(stats_mu_);
      stats_.connected = false;
      have_tseq_ = false;
      have_last_status_ = false;
    }
    post_event({LinkEvent::Kind::Down, down_words(link_.path(), why)});
  };
  h.on_up = [this] {
    last_frame_ns_ = now_ns();
    if (peer_ == Peer::Unchecked) {
      event_cv_.notify_all();  // the supervisor asks who answers (check_peer)
      return;
    }
    {
      std::lock_guard<std::mutex> lock(stats_mu_);
      stats_.connected = true;
      ++stats_.reconnects;
    }
    post_event({LinkEvent::Kind::Up, reopened_words(link_.path())});
  };
  {
    std::lock_guard<std::mutex> lock(identity_mu_);
    peer_ = Peer::Known;
    have_identity_ = false;
  }
  {
    std::lock_guard<std::mutex> lock(stats_mu_);
    for (bool& said : said_refused_) said = false;
  }
  {
    std::lock_guard<std::mutex> lock(port_mu_);
    port_ = path;
  }
  link_.open(path, baud, std::move(h));
  {
    std::lock_guard<std::mutex> lock(stats_mu_);
    stats_.connected = true;
  }
  last_frame_ns_ = now_ns();
  stopping_ = false;
  supervisor_ = std::thread([this] { supervise(); });
}

void Session::close() {
  link_.close();
  if (supervisor_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(event_mu_);
      stopping_ = true;
    }
    event_cv_.notify_all();
    supervisor_.join();
  }
  // What the closed link said and the supervisor had not passed on stays
  // with it: the next open() would deliver it as the new port's own.
  std::lock_guard<std::mutex> lock(event_mu_);
  events_.clear();
}

void Session::post_event(LinkEvent e) {
  {
    std::lock_guard<std::mutex> lock(event_mu_);
    events_.push_back(std::move(e));
  }
  event_cv_.notify_all();
}

void Session::supervise() {
  auto last_rate = Clock::now();
  uint64_t last_frames = 0, last_bytes = 0;
  bool silent = false;
  uint64_t frames_at_silence = 0;
  auto next_check = Clock::now();
  std::unique_lock<std::mutex> lock(event_mu_);
  while (!stopping_) {
    event_cv_.wait_for(lock, std::chrono::milliseconds(100));
    std::vector<LinkEvent> batch;
    batch.swap(events_);
    lock.unlock();
    // Silence: the port is open but nothing valid arrives (board hung,
    // wrong baud, firmware of another protocol version).
    const int64_t quiet_ns = now_ns() - last_frame_ns_.load();
    const bool now_silent =
        connected() && quiet_ns > std::chrono::nanoseconds(options_.silence_limit).count();
    uint64_t frames_now = 0;
    {
      std::lock_guard<std::mutex> st(stats_mu_);
      frames_now = stats_.frames;
    }
    // "Frames arriving again" only when frames did: a silence that ends
    // because the port went down or was reopened is told by Down and Up.
    if (now_silent != silent && !now_silent && frames_now == frames_at_silence) {
      silent = false;
    } else if (now_silent != silent) {
      silent = now_silent;
      frames_at_silence = frames_now;
      const bool echoing =
          silent && now_ns() - last_echo_ns_.load() < std::chrono::nanoseconds(options_.silence_limit).count();
      const std::string detail = silence_words(silent, options_.silence_limit, echoing,
                                               silent ? other_openers(link_.path()) : std::vector<PortOpener>{});
      batch.push_back({silent ? LinkEvent::Kind::Silent : LinkEvent::Kind::Resumed, detail});
    }
    const auto now = Clock::now();
    const double dt = std::chrono::duration<double>(now - last_rate).count();
    {
      std::lock_guard<std::mutex> s(stats_mu_);
      stats_.silent = silent;
      if (dt >= 1.0) {
        stats_.frames_per_s = double(stats_.frames - last_frames) / dt;
        stats_.bytes_per_s = double(stats_.bytes - last_bytes) / dt;
        last_frames = stats_.frames;
        last_bytes = stats_.bytes;
        last_rate = now;
      }
    }
    for (const LinkEvent& e : batch)
      if (event_handler_) event_handler_(e);
    // A peer that does not answer yet (a board still booting) is asked
    // again at the reconnect interval.
    if (peer_ == Peer::Unchecked && link_.is_up() && Clock::now() >= next_check) {
      check_peer();
      next_check = Clock::now() + options_.reconnect_interval;
    }
    keepalive();
    lock.lock();
  }
}

void Session::on_bytes(const uint8_t* data, size_t len) {
  {
    std::lock_guard<std::mutex> lock(stats_mu_);
    stats_.bytes += len;
  }
  size_t used = 0;
  while (used < len) {
    p::DecodeResult r;
    used += decoder_.feed(data + used, len - used, r);
    if (r.kind == p::DecodeResult::Kind::Frame) {
      // A request (console -> firmware) that is not a reply is one of ours
      // come back: the line echoes. Not a sign of a firmware.
      if (!r.frame.is_reply() && r.frame.header.type < uint8_t(p::MsgType::Ack)) {
        last_echo_ns_ = now_ns();
        std::lock_guard<std::mutex> lock(stats_mu_);
        ++stats_.echoed_frames;
        continue;
      }
      last_frame_ns_ = now_ns();
      on_frame(r.frame);
    } else if (r.kind == p::DecodeResult::Kind::Error) {
      std::lock_guard<std::mutex> lock(stats_mu_);
      if (r.error == p::FrameError::BadCrc)
        ++stats_.crc_errors;
      else
        ++stats_.decode_errors;
      // The version byte is read before the CRC can be, so line noise
      // "speaks" a random version now and then: only the same one three
      // times running is taken for a firmware of another protocol.
      if (r.error == p::FrameError::WrongVersion) {
        const uint8_t v = r.frame.header.version;
        foreign_streak_ = v == foreign_candidate_ ? foreign_streak_ + 1 : 1;
        foreign_candidate_ = v;
        if (foreign_streak_ >= 3) foreign_version_ = v;
      }
    }
  }
}

void Session::on_frame(const p::FrameView& f) {
  {
    std::lock_guard<std::mutex> lock(stats_mu_);
    ++stats_.frames;
  }
  // Frames of a peer not (yet) known to be our device are not ours; only the
  // reply to the identifying INFO_GET is taken (on_reply checks).
  if (peer_ != Peer::Known) {
    if (f.is_reply()) on_reply(f);
    return;
  }
  const auto type = p::MsgType(f.header.type);
  if (f.is_reply()) on_reply(f);
  // The sample frames' dimensions against INFO's, once, here: past this
  // point a sample's vectors are the firmware's shape (sample_check.hpp).
  std::optional<p::Info> info;
  if (type == p::MsgType::Telemetry || type == p::MsgType::IdentSample || type == p::MsgType::SensorSample) {
    std::lock_guard<std::mutex> lock(identity_mu_);
    if (have_identity_) info = identity_;
  }
  if (type == p::MsgType::Telemetry) {
    p::Telemetry t;
    if (p::unpack(f, t) != p::StatusCode::Ok) return;
    if (const auto fault = telemetry_fault(t, info ? &*info : nullptr); fault != SampleFault::None)
      return refuse_sample(int(fault), telemetry_refusal(t, info ? &*info : nullptr));
    const uint32_t lost = count_telemetry(t.tseq);
    if (telemetry_handler_) telemetry_handler_(t, lost);
  } else if (type == p::MsgType::IdentSample) {
    p::IdentSample t;
    if (p::unpack(f, t) != p::StatusCode::Ok) return;
    if (const auto fault = ident_sample_fault(t, info ? &*info : nullptr); fault != SampleFault::None)
      return refuse_sample(int(fault), ident_sample_refusal(t, info ? &*info : nullptr));
    const uint32_t lost = count_telemetry(t.tseq);
    if (ident_handler_) ident_handler_(t, lost);
  } else if (type == p::MsgType::SensorHealth) {
    p::SensorHealth h;
    if (p::unpack(f, h) == p::StatusCode::Ok && health_handler_) health_handler_(h);
  } else if (type == p::MsgType::SensorSample) {
    p::SensorSample s;
    if (p::unpack(f, s) != p::StatusCode::Ok) return;
    if (const auto fault = sensor_sample_fault(s, info ? &*info : nullptr); fault != SampleFault::None)
      return refuse_sample(int(fault), sensor_sample_refusal(s, info ? &*info : nullptr));
    if (sensor_sample_handler_) sensor_sample_handler_(s);
  } else if (type == p::MsgType::Status) {
    p::Status s;
    if (p::unpack(f, s) != p::StatusCode::Ok) return;
    {
      std::lock_guard<std::mutex> lock(stats_mu_);
      const bool running =
          s.run_state == uint8_t(p::RunState::Running) || s.run_state == uint8_t(p::RunState::Ident);
      if (have_last_status_ && running && last_status_.run_state == s.run_state &&
          last_status_.run_id == s.run_id && s.uptime_ms > last_status_.uptime_ms && s.step >= last_status_.step) {
        stats_.loop_rate_hz = 1000.0 * double(s.step - last_status_.step) / double(s.uptime_ms - last_status_.uptime_ms);
      } else if (!running) {
        stats_.loop_rate_hz = nominal_rate_hz_;
      }
      const double tick = s.tick_rate_hz ? 1e6 / double(s.tick_rate_hz) : 0.0;
      stats_.compute_mean_us = double(s.compute_mean) * tick;
      stats_.compute_max_us = double(s.compute_max) * tick;
      stats_.fw_crc_errors = s.crc_errors;
      stats_.fw_frame_errors = s.frame_errors;
      stats_.fw_tx_dropped = s.tx_dropped;
      stats_.fw_loop_overruns = s.loop_overruns;
      stats_.run_state = s.run_state;
      stats_.run_id = s.run_id;
      stats_.step = s.step;
      stats_.have_status = true;
      last_status_ = s;
      have_last_status_ = true;
    }
    if (status_handler_) status_handler_(s);
  } else if (type == p::MsgType::Log) {
    p::Log l;
    if (p::unpack(f, l) != p::StatusCode::Ok) return;
    // The firmware's text is escaped where it becomes a string: no handler
    // (a terminal, the session log, the database) ever holds it raw.
    printable_into(l.text, l.text, sizeof l.text);
    if (log_handler_) log_handler_(l);
  }
}

void Session::refuse_sample(int fault, const std::string& words) {
  bool say = false;
  {
    std::lock_guard<std::mutex> lock(stats_mu_);
    ++stats_.refused_frames;
    // Counted lost: the tseq of the next frame taken shows the gap.
    if (fault >= 0 && fault < int(std::size(said_refused_)) && !said_refused_[fault]) say = said_refused_[fault] = true;
  }
  if (say)
    post_event({LinkEvent::Kind::Refused,
                fmt::format("dropped {}; every such frame is dropped and counted as lost (said once)", words)});
}

void Session::on_reply(const p::FrameView& f) {
  {
    std::lock_guard<std::mutex> lock(pending_mu_);
    // The tap runs under the lock that a new request takes to become
    // pending: by the time a tap's user has counted this reply and sends
    // its seq again, the session has already matched or discarded it. (Run
    // before the lock, a late duplicate counted by the conformance probe was
    // matched to the request it sent next with that seq: TSan under load.)
    if (any_reply_handler_) any_reply_handler_(f);
    if (pending_active_ && !pending_done_ && f.header.seq == pending_seq_ && answers(pending_type_, f) &&
        (pending_identifying_ || peer_ == Peer::Known)) {
      pending_reply_.type = f.header.type;
      pending_reply_.seq = f.header.seq;
      pending_reply_.length = f.header.length;
      std::memcpy(pending_reply_.payload, f.payload, f.header.length);
      pending_done_ = true;
      pending_cv_.notify_all();
      return;
    }
  }
  // A reply to a retransmission we no longer wait for, or to a request from
  // before a reconnect: the firmware repeats replies by design.
  std::lock_guard<std::mutex> lock(stats_mu_);
  ++stats_.stale_replies;
}

Reply Session::transact(uint8_t type, const uint8_t* payload, size_t length) {
  std::lock_guard<std::mutex> serial(request_mu_);
  const Reply r = transact_locked(type, payload, length);
  // The device's identity, to recognise it after a reconnect.
  p::InfoEx info;
  if (unpack_info(r, info)) {
    // Its name is said when another device answers: escaped here, as read.
    printable_into(info.info.firmware, info.info.firmware, sizeof info.info.firmware);
    std::lock_guard<std::mutex> lock(identity_mu_);
    identity_ = info.info;
    have_identity_ = true;
  }
  return r;
}

// After a reopen, on the supervisor thread: INFO_GET to whatever answers at
// the port now. The same identity makes it the link we had (Up); another
// one is reported in words and refused (Foreign). No answer leaves it
// Unchecked, to be asked again.
void Session::check_peer() {
  const uint64_t losses = losses_.load();
  Reply r;
  {
    std::lock_guard<std::mutex> serial(request_mu_);
    try {
      r = transact_locked(uint8_t(p::MsgType::InfoGet), nullptr, 0, /*identifying=*/true);
    } catch (const LinkError&) {
      return;
    }
  }
  p::InfoEx now_ex;
  p::Info& now = now_ex.info;
  std::string refusal;
  {
    std::lock_guard<std::mutex> lock(identity_mu_);
    // Lost again while asking: the answer may be from the port before; the
    // next reopen is checked anew.
    if (losses_ != losses) return;
    std::string change;
    if (!unpack_info(r, now_ex)) {
      change = not_info_words(r.type);
    } else {
      printable_into(now.firmware, now.firmware, sizeof now.firmware);
      change = identity_change(identity_, now);
    }
    if (change.empty()) {
      identity_ = now;  // the hashes may have changed; the console re-reads them
      peer_ = Peer::Known;
    } else {
      refusal = foreign_ = foreign_words(link_.path(), change);
      peer_ = Peer::Foreign;
    }
  }
  if (!refusal.empty()) {
    post_event({LinkEvent::Kind::Foreign, refusal});
    return;
  }
  {
    std::lock_guard<std::mutex> lock(stats_mu_);
    stats_.connected = true;
    ++stats_.reconnects;
  }
  last_frame_ns_ = now_ns();
  post_event({LinkEvent::Kind::Up, same_device_words(link_.path())});
}

void Session::keepalive() {
  if (options_.keepalive.count() == 0 || !connected()) return;
  if (now_ns() - last_tx_ns_.load() < std::chrono::nanoseconds(options_.keepalive).count()) return;
  // A request in flight is traffic already; never queue behind it.
  std::unique_lock<std::mutex> serial(request_mu_, std::try_to_lock);
  if (!serial.owns_lock()) return;
  p::Ping ping;
  ping.nonce = ++ping_nonce_;
  uint8_t payload[4];
  size_t len = 0;
  if (p::pack(ping, payload, sizeof payload, len) != p::StatusCode::Ok) return;
  try {
    transact_locked(uint8_t(p::MsgType::Ping), payload, len);
  } catch (const LinkError&) {
    // Counted as a timeout; the silence detector reports a dead link.
  }
}

uint8_t Session::next_seq() {
  std::lock_guard<std::mutex> serial(request_mu_);
  return next_seq_++;
}

void Session::write_raw(const std::vector<uint8_t>& bytes) {
  last_tx_ns_ = now_ns();
  if (link_.is_up()) link_.write(bytes);
}

std::optional<Reply> Session::exchange(const RawRequest& req) {
  std::lock_guard<std::mutex> serial(request_mu_);
  int sent = 0;
  return exchange_locked(req, false, sent);
}

std::optional<Reply> Session::exchange_locked(const RawRequest& req, bool identifying, int& sent) {
  {
    std::lock_guard<std::mutex> lock(pending_mu_);
    pending_active_ = true;
    pending_done_ = false;
    pending_seq_ = req.seq;
    pending_type_ = req.type;
    pending_identifying_ = identifying;
  }
  auto wait = req.timeout;
  for (int attempt = 0; attempt < req.tries; ++attempt, wait = req.backoff ? 2 * wait : wait) {
    if (attempt > 0) {
      std::lock_guard<std::mutex> lock(stats_mu_);
      ++stats_.retransmits;
    }
    last_tx_ns_ = now_ns();
    // A peer not known to be our device gets nothing but the identifying
    // INFO_GET; the request waits as on a down link, for it to be checked.
    if (link_.is_up() && (identifying || peer_ == Peer::Known)) {
      if (req.write_chunk == 0) {
        link_.write(req.wire);
      } else {
        for (size_t off = 0; off < req.wire.size(); off += req.write_chunk) {
          const size_t end = std::min(req.wire.size(), off + req.write_chunk);
          link_.write(std::vector<uint8_t>(req.wire.begin() + long(off), req.wire.begin() + long(end)));
          if (req.chunk_gap.count() > 0) std::this_thread::sleep_for(req.chunk_gap);
        }
      }
      ++sent;
    }
    std::unique_lock<std::mutex> lock(pending_mu_);
    // The reply may belong to any earlier try (same seq): whichever arrives
    // first under this mutex wins, and a later copy counts as stale.
    if (pending_cv_.wait_for(lock, wait, [this] { return pending_done_; })) {
      pending_active_ = false;
      return pending_reply_;
    }
  }
  std::lock_guard<std::mutex> lock(pending_mu_);
  pending_active_ = false;
  return std::nullopt;
}

Reply Session::transact_locked(uint8_t type, const uint8_t* payload, size_t length, bool identifying) {
  uint8_t wire[p::kWireBufferSize];
  const uint8_t seq = next_seq_++;
  const size_t n = p::encode_frame(type, seq, 0, payload, length, wire, sizeof wire);
  if (n == 0) throw LinkError(unencodable_words(type));
  // XFER_COMMIT validates a whole object, SETTINGS erases a flash sector (PROTOCOL.md 10).
  const auto per_try = type == uint8_t(p::MsgType::XferCommit) || type == uint8_t(p::MsgType::Settings)
                           ? options_.commit_timeout
                           : options_.timeout;
  LinkStats before;
  {
    std::lock_guard<std::mutex> lock(stats_mu_);
    before = stats_;
  }
  RawRequest req;
  req.wire.assign(wire, wire + n);
  req.type = type;
  req.seq = seq;
  req.tries = options_.tries;
  req.timeout = per_try;
  int sent = 0;
  const auto began = Clock::now();
  if (auto r = exchange_locked(req, identifying, sent)) return *r;
  NoReply why;
  why.waited = Clock::now() - began;
  {
    std::lock_guard<std::mutex> lock(stats_mu_);
    ++stats_.timeouts;
  }
  why.type = type;
  why.sent = sent;
  why.tries = options_.tries;
  why.per_try = per_try;
  why.port = link_.path();
  why.up = link_.is_up();
  why.will_reopen = link_.will_reopen();
  const Peer peer = peer_.load();
  if (why.up && peer == Peer::Known) {
    why.heard = heard_since(before);
    why.others = other_openers(link_.path());
  }
  why.unchecked = peer == Peer::Unchecked;
  if (peer == Peer::Foreign) {
    std::lock_guard<std::mutex> lock(identity_mu_);
    why.foreign = foreign_;
  }
  why.foreign_version = foreign_version_.load();
  throw LinkError(no_reply_words(why));
}

void Session::throw_nack(const Reply& r) const {
  p::Nack nack;
  if (p::unpack(r.payload, r.length, nack) != p::StatusCode::Ok) unexpected(r, 0);
  throw NackError(nack, describe_nack(nack));
}

void Session::unexpected(const Reply& r, uint8_t request_type) const {
  throw LinkError(unexpected_reply_words(r.type, r.length, request_type));
}

LineHeard Session::heard_since(const LinkStats& before) const {
  const LinkStats now = stats();
  LineHeard h;
  h.bytes = now.bytes - before.bytes;
  h.frames = now.frames - before.frames;
  // Echoed frames never count as frames (on_bytes sets them apart).
  const uint64_t echoed = now.echoed_frames - before.echoed_frames;
  h.version = foreign_version_.load();
  if (h.bytes == 0) h.kind = LineHeard::Kind::Nothing;
  else if (h.version != 0) h.kind = LineHeard::Kind::OtherVersion;
  else if (h.frames == 0 && echoed > 0) {
    h.kind = LineHeard::Kind::Echo;
    h.frames = echoed;
  } else if (h.frames == 0) h.kind = LineHeard::Kind::Noise;
  else h.kind = LineHeard::Kind::Frames;
  return h;
}

std::string Session::no_info_words(const LinkStats& before, Clock::duration waited, unsigned baud) const {
  return console::no_info_words(heard_since(before), link_.path(), waited, baud, link_.is_up());
}

LinkStats Session::stats() const {
  std::lock_guard<std::mutex> lock(stats_mu_);
  LinkStats s = stats_;
  s.connected = connected();
  return s;
}

}  // namespace nlsoft::console
