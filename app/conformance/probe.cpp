#include "app/conformance/probe.hpp"

#include "app/link/port_openers.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <thread>

namespace nlsoft::console::conformance {

namespace {

SessionOptions probe_options(Ms timeout) {
  SessionOptions o;
  o.timeout = timeout;
  o.commit_timeout = std::max(timeout, Ms(1500));
  // The suite decides when the link is quiet: the watchdog checks need
  // silence, and a keepalive PING would be traffic the checks did not send.
  o.keepalive = Ms(0);
  return o;
}

}  // namespace

bool as_info(const Frame& f, p::InfoEx& out) {
  Reply r;
  r.type = f.type;
  r.seq = f.seq;
  r.length = uint8_t(std::min<size_t>(f.payload.size(), sizeof r.payload));
  std::copy(f.payload.begin(), f.payload.begin() + r.length, r.payload);
  return unpack_info(r, out);
}

std::string describe(const Frame& f) {
  p::Nack n;
  if (as(f, n)) return "NACK: " + describe_nack(n);
  return p::message_name(f.type);
}

bool acked(const Frame& f, p::MsgType request) {
  p::Ack a;
  return as(f, a) && a.request_type == uint8_t(request);
}

bool nacked(const Frame& f, p::StatusCode status, uint8_t field, uint8_t element) {
  p::Nack n;
  return as(f, n) && n.status == uint8_t(status) && n.field == field && n.element == element;
}

Probe::Probe(Ms timeout) : timeout_(timeout), session_(probe_options(timeout)) {
  session_.on_any_reply([this](const p::FrameView& f) {
    std::lock_guard<std::mutex> lock(mu_);
    ++replies_;
    ++answers_[f.header.seq];
    answered_cv_.notify_all();
    types_seen_.insert(f.header.type);
    if (std::find(recent_seqs_.begin(), recent_seqs_.end(), f.header.seq) == recent_seqs_.end()) {
      ++foreign_;
      if (first_foreign_.empty())
        first_foreign_ = fmt::format("{} with seq {}", p::message_name(f.header.type), f.header.seq);
    }
    if (listening_ && !listen_ignores_.count(f.header.seq))
      heard_.push_back({f.header.type, f.header.seq, {f.payload, f.payload + f.header.length}});
  });
  session_.on_telemetry([this](const p::Telemetry& t, uint32_t) {
    std::lock_guard<std::mutex> lock(mu_);
    types_seen_.insert(uint8_t(p::MsgType::Telemetry));
    if (recording_) {
      const bool paired = sensors_ && sensors_->step == t.step;
      if (sensors_ && !paired) ++stray_sensors_;
      telemetry_.push_back({t.tseq, t.step, paired ? int(sensors_->w) : -1});
    }
    sensors_.reset();
  });
  session_.on_sensor_sample([this](const p::SensorSample& s) {
    std::lock_guard<std::mutex> lock(mu_);
    types_seen_.insert(uint8_t(p::MsgType::SensorSample));
    if (recording_ && sensors_) ++stray_sensors_;
    sensors_ = s;
  });
  session_.on_ident_sample([this](const p::IdentSample& t, uint32_t) {
    std::lock_guard<std::mutex> lock(mu_);
    types_seen_.insert(uint8_t(p::MsgType::IdentSample));
    if (ident_.size() < 100000) ident_.push_back(t);
  });
  session_.on_sensor_health([this](const p::SensorHealth&) {
    std::lock_guard<std::mutex> lock(mu_);
    types_seen_.insert(uint8_t(p::MsgType::SensorHealth));
  });
  session_.on_status([this](const p::Status& s) {
    std::lock_guard<std::mutex> lock(mu_);
    types_seen_.insert(uint8_t(p::MsgType::Status));
    statuses_.push_back(s);
    if (statuses_.size() > 1000) statuses_.erase(statuses_.begin());
  });
  session_.on_log([this](const p::Log& l) {
    std::lock_guard<std::mutex> lock(mu_);
    types_seen_.insert(uint8_t(p::MsgType::Log));
    logs_.emplace_back(l.text);
  });
}

Probe::~Probe() { session_.close(); }

void Probe::open(const std::string& path, unsigned baud) {
  baud_ = baud;
  session_.open(path, baud);
  session_.write_raw({p::kDelimiter});  // ends whatever partial frame the peer holds
}

uint8_t Probe::next_seq() {
  const uint8_t seq = session_.next_seq();
  note_sent(seq);
  std::lock_guard<std::mutex> lock(mu_);
  copies_[seq] = answers_[seq] = 0;  // a seq come round again starts afresh
  return seq;
}

void Probe::settle(uint8_t seq) {
  // Every copy of a request is answered (a duplicate from the stored reply),
  // in the order written. A copy whose answer never comes within the
  // patience of one request (250 + 500 + 1000 + 2000 ms at --timeout 250)
  // was lost on the line: nothing late is left to mistake.
  std::unique_lock<std::mutex> lock(mu_);
  answered_cv_.wait_for(lock, 15 * timeout_, [&] { return answers_[seq] >= copies_[seq]; });
}

void Probe::note_sent(uint8_t seq) {
  std::lock_guard<std::mutex> lock(mu_);
  recent_seqs_.push_back(seq);
  if (recent_seqs_.size() > 32) recent_seqs_.pop_front();
}

std::vector<uint8_t> Probe::wire(uint8_t type, uint8_t seq, const uint8_t* payload, size_t len, uint8_t flags) {
  uint8_t buf[p::kWireBufferSize];
  const size_t n = p::encode_frame(type, seq, flags, payload, len, buf, sizeof buf);
  if (n == 0) throw LinkError(fmt::format("cannot encode a {} frame", p::message_name(type)));
  return {buf, buf + n};
}

Frame Probe::exchange(uint8_t type, uint8_t seq, const std::vector<uint8_t>& bytes, int tries, size_t write_chunk,
                      Ms chunk_gap) {
  RawRequest req;
  req.wire = bytes;
  req.type = type;
  req.seq = seq;
  req.tries = tries;
  req.timeout = type == uint8_t(p::MsgType::XferCommit) ? std::max(timeout_, Ms(1500)) : timeout_;
  req.backoff = true;
  req.write_chunk = write_chunk;
  req.chunk_gap = chunk_gap;
  LinkStats before;
  const auto began = std::chrono::steady_clock::now();
  const auto r = send(req, before);
  if (!r) {
    std::string waits;
    for (int i = 0; i < tries; ++i) waits += fmt::format("{}{}", i ? ", " : "", req.timeout.count() << i);
    throw LinkError(fmt::format("no reply to {} seq {} after {} tries ({} ms); meanwhile {}", p::message_name(type),
                                seq, tries, waits, heard_while_waiting(before)));
  }
  if (session_.stats().retransmits != before.retransmits) {
    const auto waited = std::chrono::duration_cast<Ms>(std::chrono::steady_clock::now() - began);
    std::lock_guard<std::mutex> lock(mu_);
    ++late_.requests;
    if (waited > late_.longest) {
      late_.longest = waited;
      late_.longest_request = fmt::format("{} seq {}", p::message_name(type), seq);
    }
  }
  return *r;
}

std::optional<Frame> Probe::send(const RawRequest& req, LinkStats& before) {
  note_sent(req.seq);
  settle(req.seq);
  before = session_.stats();
  const auto reply = session_.exchange(req);
  {
    // Only this thread writes (no keepalive): every try beyond the first is one more copy.
    std::lock_guard<std::mutex> lock(mu_);
    copies_[req.seq] += 1 + unsigned(session_.stats().retransmits - before.retransmits);
  }
  return done(req.type, reply);
}

Probe::Late Probe::late() const {
  std::lock_guard<std::mutex> lock(mu_);
  return late_;
}

// Tells a silent device (or a stalled emulator: nothing at all arrived) from
// one that kept sending but never answered, and whether the firmware's own
// STATUS counted our frames as damaged.
std::string Probe::heard_while_waiting(const LinkStats& before) const {
  const LineHeard h = session_.heard_since(before);
  const LinkStats now = session_.stats();
  std::string words =
      h.kind == LineHeard::Kind::Frames
          ? fmt::format("{} frames arrived from {} ({} TELEMETRY), none of them the reply", h.frames, session_.port(),
                        now.telemetry_frames - before.telemetry_frames)
          : heard_words(h, session_.port());
  if (now.have_status && before.have_status &&
      (now.fw_crc_errors != before.fw_crc_errors || now.fw_frame_errors != before.fw_frame_errors))
    words += fmt::format("; the firmware's STATUS counted crc_errors +{}, frame_errors +{}",
                         now.fw_crc_errors - before.fw_crc_errors, now.fw_frame_errors - before.fw_frame_errors);
  // A second reader of the port takes the bytes meant for us: name it.
  if (const auto others = other_openers(session_.port()); !others.empty())
    words += "; " + also_open_words(others, session_.port());
  return words;
}

std::optional<Frame> Probe::done(uint8_t type, const std::optional<Reply>& r) {
  if (!r) return std::nullopt;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (r->type != uint8_t(p::MsgType::Nack)) answered_.insert(type);
    taken_seqs_.push_back(r->seq);
    if (taken_seqs_.size() > 32) taken_seqs_.pop_front();
  }
  return Frame{r->type, r->seq, {r->payload, r->payload + r->length}};
}

std::set<uint8_t> Probe::answered() const {
  std::lock_guard<std::mutex> lock(mu_);
  return answered_;
}

std::optional<Frame> Probe::try_exchange(uint8_t type, uint8_t seq, const std::vector<uint8_t>& bytes, Ms wait) {
  RawRequest req;
  req.wire = bytes;
  req.type = type;
  req.seq = seq;
  req.timeout = wait;
  LinkStats before;
  return send(req, before);
}

void Probe::listen() {
  std::lock_guard<std::mutex> lock(mu_);
  heard_.clear();
  listen_ignores_ = std::set<uint8_t>(taken_seqs_.begin(), taken_seqs_.end());
  listening_ = true;
}

std::vector<Frame> Probe::stop_listening() {
  std::lock_guard<std::mutex> lock(mu_);
  listening_ = false;
  return std::move(heard_);
}

// A pty hands a burst to the firmware at once; a serial line brings it at
// its baud (4 kB at 115200: 350 ms). Written at the line's rate, in 64-byte
// pieces, a burst arrives as a board's line would bring it, so the checks
// test the firmware's framing, not a rate no link it serves can reach (a
// 4 kB burst at once overran an image's 512-byte ring while its loop waited
// on a servo, tests/firmware/servos_qemu.sh).
void Probe::write_at_line_rate(const std::vector<uint8_t>& bytes) {
  constexpr size_t kPiece = 64;
  const auto per_piece =
      std::chrono::microseconds(baud_ > 0 ? uint64_t(kPiece) * 10u * 1000000u / uint64_t(baud_) : 0u);
  for (size_t at = 0; at < bytes.size(); at += kPiece) {
    const auto due = std::chrono::steady_clock::now() + per_piece;
    const auto end = bytes.begin() + std::ptrdiff_t(std::min(bytes.size(), at + kPiece));
    session_.write_raw(std::vector<uint8_t>(bytes.begin() + std::ptrdiff_t(at), end));
    if (end != bytes.end()) std::this_thread::sleep_until(due);
  }
}

std::vector<Frame> Probe::send_fenced(const std::vector<uint8_t>& bytes, const p::Ping& fence, Frame& answer) {
  listen();
  write_at_line_rate(bytes);
  const uint8_t seq = next_seq();
  try {
    answer = exchange(uint8_t(p::MsgType::Ping), seq, wire(fence, seq));
  } catch (...) {
    stop_listening();
    throw;
  }
  std::vector<Frame> heard = stop_listening();
  heard.erase(std::remove_if(heard.begin(), heard.end(), [seq](const Frame& f) { return f.seq == seq; }), heard.end());
  return heard;
}

void Probe::record_telemetry(bool on) {
  std::lock_guard<std::mutex> lock(mu_);
  recording_ = on;
  if (on) {
    telemetry_.clear();
    stray_sensors_ = 0;
    sensors_.reset();
  }
}

unsigned Probe::stray_sensor_samples() const {
  std::lock_guard<std::mutex> lock(mu_);
  return stray_sensors_;
}

std::vector<TelemetrySample> Probe::telemetry() {
  std::lock_guard<std::mutex> lock(mu_);
  return telemetry_;
}

std::vector<p::IdentSample> Probe::take_ident_samples() {
  std::lock_guard<std::mutex> lock(mu_);
  return std::move(ident_);
}

std::vector<p::Status> Probe::take_statuses() {
  std::lock_guard<std::mutex> lock(mu_);
  return std::move(statuses_);
}

std::vector<std::string> Probe::take_logs() {
  std::lock_guard<std::mutex> lock(mu_);
  return std::move(logs_);
}

std::set<uint8_t> Probe::types_seen() const {
  std::lock_guard<std::mutex> lock(mu_);
  return types_seen_;
}

unsigned Probe::replies() const {
  std::lock_guard<std::mutex> lock(mu_);
  return replies_;
}

unsigned Probe::foreign_replies() const {
  std::lock_guard<std::mutex> lock(mu_);
  return foreign_;
}

std::string Probe::first_foreign() const {
  std::lock_guard<std::mutex> lock(mu_);
  return first_foreign_;
}

}  // namespace nlsoft::console::conformance
