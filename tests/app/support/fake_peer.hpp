#pragma once
// An in-process stand-in for the firmware on a pseudo-terminal: the console
// code under test opens the pty's slave path as it would a serial port, and
// a handler decides per request what the "firmware" does (reply, stay
// silent, reply late, reply twice, NACK).
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "protocol/decoder.hpp"
#include "protocol/encoder.hpp"

namespace nlsoft::test {

class FakePeer {
 public:
  using Handler = std::function<void(FakePeer& peer, const protocol::FrameView& request)>;

  explicit FakePeer(Handler h) : handler_(std::move(h)) {
    char name[128];
    termios raw{};
    cfmakeraw(&raw);
    if (openpty(&master_, &slave_, name, &raw, nullptr) != 0) throw std::runtime_error("openpty failed");
    path_ = name;
    thread_ = std::thread([this] { loop(); });
  }
  ~FakePeer() { stop(); }

  void stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    if (master_ >= 0) ::close(master_), master_ = -1;
    if (slave_ >= 0) ::close(slave_), slave_ = -1;
  }

  const std::string& path() const { return path_; }

  template <class M>
  void reply(const M& msg, uint8_t seq) {
    uint8_t buf[protocol::kWireBufferSize];
    const size_t n = protocol::encode_reply(msg, seq, buf, sizeof buf);
    write(buf, n);
  }
  template <class M>
  void send_unsolicited(const M& msg, uint8_t seq = 0) {
    uint8_t buf[protocol::kWireBufferSize];
    const size_t n = protocol::encode(msg, seq, 0, buf, sizeof buf);
    write(buf, n);
  }
  void write(const uint8_t* data, size_t n) {
    std::lock_guard<std::mutex> lock(write_mu_);
    while (n > 0) {
      const ssize_t w = ::write(master_, data, n);
      if (w <= 0) return;
      data += w;
      n -= size_t(w);
    }
  }

  int requests_seen() const { return requests_.load(); }
  std::vector<uint8_t> seqs_seen() {
    std::lock_guard<std::mutex> lock(seen_mu_);
    return seqs_;
  }

 private:
  void loop() {
    protocol::Decoder dec;
    uint8_t buf[512];
    while (!stop_) {
      pollfd pfd{master_, POLLIN, 0};
      if (::poll(&pfd, 1, 20) <= 0) continue;
      const ssize_t n = ::read(master_, buf, sizeof buf);
      if (n <= 0) continue;
      size_t used = 0;
      while (used < size_t(n)) {
        protocol::DecodeResult r;
        used += dec.feed(buf + used, size_t(n) - used, r);
        if (r.kind != protocol::DecodeResult::Kind::Frame) continue;
        ++requests_;
        {
          std::lock_guard<std::mutex> lock(seen_mu_);
          seqs_.push_back(r.frame.header.seq);
        }
        handler_(*this, r.frame);
      }
    }
  }

  Handler handler_;
  int master_ = -1, slave_ = -1;
  std::string path_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<int> requests_{0};
  std::mutex write_mu_, seen_mu_;
  std::vector<uint8_t> seqs_;
};

}  // namespace nlsoft::test
