#pragma once
// Test support: a minimal console side over a tty fd, built on the protocol
// library. Blocking, single-threaded, with timeouts: enough to drive the
// firmware through its exchanges in a test.
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "protocol/decoder.hpp"
#include "protocol/encoder.hpp"
#include "protocol/messages.hpp"
#include "shared/params.hpp"
#include <gtest/gtest.h>
#include <initializer_list>

namespace nlsoft::test {

namespace proto = nlsoft::protocol;

struct Received {
  proto::Header header;
  std::vector<uint8_t> payload;
  proto::FrameView view() const {
    proto::FrameView v;
    v.header = header;
    v.payload = payload.data();
    return v;
  }
};

// A received frame as a typed message (the test fails if it does not unpack).
template <class M>
M as(const Received& r) {
  M m;
  EXPECT_EQ(proto::unpack(r.view(), m), proto::StatusCode::Ok);
  return m;
}

// PARAM_SET of float values.
inline proto::ParamSet param_set(ParamId id, std::initializer_list<float> v) {
  proto::ParamSet p;
  p.id = uint16_t(id);
  for (float x : v) p.set_f32(p.count++, x);
  return p;
}

class Peer {
 public:
  explicit Peer(const std::string& path) {
    fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (fd_ >= 0) {
      termios t{};
      tcgetattr(fd_, &t);
      cfmakeraw(&t);
      tcsetattr(fd_, TCSANOW, &t);
      const uint8_t z = 0;
      (void)!::write(fd_, &z, 1);  // end whatever partial frame the firmware holds
    }
  }
  ~Peer() {
    if (fd_ >= 0) ::close(fd_);
  }
  bool ok() const { return fd_ >= 0; }
  int fd() const { return fd_; }

  void send_raw(const uint8_t* data, size_t len) {
    size_t off = 0;
    while (off < len) {
      const ssize_t w = ::write(fd_, data + off, len - off);
      if (w > 0) off += size_t(w);
      else wait(POLLOUT, 10);
    }
  }

  template <class M>
  uint8_t send(const M& msg) {
    uint8_t wire[proto::kWireBufferSize];
    const uint8_t seq = seq_++;
    const size_t len = proto::encode(msg, seq, 0, wire, sizeof wire);
    send_raw(wire, len);
    return seq;
  }

  // Sends a request and waits for the reply with its seq, of a type that
  // answers it (protocol/catalog.hpp, as the console matches); unsolicited
  // frames seen meanwhile go to `unsolicited`.
  template <class M>
  std::optional<Received> request(const M& msg, int timeout_ms = 1000) {
    const uint8_t seq = send(msg);
    return wait_for(
        [&](const Received& r) {
          return r.header.flags & proto::frame_flags::kReply && r.header.seq == seq &&
                 proto::answers(uint8_t(M::kType), r.header.type);
        },
        timeout_ms);
  }

  // Frames are delivered in arrival order: those before the match land in
  // `unsolicited`, bytes after it wait for the next call.
  std::optional<Received> wait_for(const std::function<bool(const Received&)>& match, int timeout_ms) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (true) {
      while (pending_pos_ < pending_.size()) {
        proto::DecodeResult d;
        pending_pos_ += decoder_.feed(pending_.data() + pending_pos_, pending_.size() - pending_pos_, d);
        if (d.kind != proto::DecodeResult::Kind::Frame) continue;
        Received rec{d.frame.header, std::vector<uint8_t>(d.frame.payload, d.frame.payload + d.frame.header.length)};
        if (match(rec)) return rec;
        unsolicited.push_back(std::move(rec));
      }
      if (std::chrono::steady_clock::now() >= until) return std::nullopt;
      uint8_t buf[4096];
      const ssize_t r = ::read(fd_, buf, sizeof buf);
      if (r <= 0) {
        wait(POLLIN, 5);
        continue;
      }
      pending_.assign(buf, buf + r);
      pending_pos_ = 0;
    }
  }

  std::vector<Received> unsolicited;
  const proto::DecoderStats& stats() const { return decoder_.stats(); }

 private:
  void wait(short ev, int ms) {
    pollfd p{fd_, ev, 0};
    ::poll(&p, 1, ms);
  }
  int fd_ = -1;
  uint8_t seq_ = 0;
  proto::Decoder decoder_;
  std::vector<uint8_t> pending_;
  size_t pending_pos_ = 0;
};

}  // namespace nlsoft::test
