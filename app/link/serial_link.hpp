#pragma once
// The byte pipe: one serial port (or pty) driven by Boost.Asio on a single
// I/O thread. It reads continuously, writes in order, and when the port
// vanishes (cable pulled, board reset, simulator gone) it closes, reports
// the loss and keeps trying to reopen the same path until told to stop --
// except a pseudo-terminal named by its own /dev/pts/N: one whose other end
// closed never comes back, and the next program to open a pty may get the
// same number (a shell, another console's simulator). A link to a pty (a
// socat link, a test's own name) is reopened: whoever made it can re-point it.
// It knows nothing about frames; Session does.
#include <boost/asio/io_context.hpp>
#include <boost/asio/serial_port.hpp>
#include <boost/asio/steady_timer.hpp>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace nlsoft::console {

class SerialLink {
 public:
  struct Handlers {
    // Called on the I/O thread; must not block.
    std::function<void(const uint8_t* data, size_t len)> on_bytes;
    std::function<void(const std::string& why)> on_down;
    std::function<void()> on_up;  // after a successful reopen
  };

  SerialLink();
  ~SerialLink();
  SerialLink(const SerialLink&) = delete;
  SerialLink& operator=(const SerialLink&) = delete;

  // Opens the port in raw 8N1 mode at `baud`, exclusively, and starts
  // reading. Throws LinkError when the port cannot be opened, is not a
  // terminal, is held by another program (named where it can be), or
  // refuses the line settings.
  void open(const std::string& path, unsigned baud, Handlers handlers);
  // Stops reading, reconnecting and the I/O thread. Idempotent.
  void close();

  // Thread-safe; silently dropped while the port is down (the request layer
  // times out and retries, which is what a lost byte would cause anyway).
  void write(std::vector<uint8_t> bytes);

  bool is_up() const { return up_.load(); }
  const std::string& path() const { return path_; }
  void set_reconnect_interval(std::chrono::milliseconds ms) { reconnect_interval_ = ms; }
  // False once a port that cannot come back (a hung-up /dev/pts/N) is lost.
  bool will_reopen() const { return will_reopen_.load(); }
  // The longest time between two writes reaching the port since the last
  // call, the time since the last write included; then starts again. The
  // firmware's watchdog counts the same silence from its end, so the two
  // figures side by side say which end held the bytes back.
  std::chrono::milliseconds take_longest_write_gap();

 private:
  std::string open_port();  // "" or why the port cannot serve
  void start_read();
  void start_write();
  void port_failed(const std::string& why);
  void schedule_reopen();

  boost::asio::io_context io_;
  boost::asio::serial_port port_;
  boost::asio::steady_timer reopen_timer_;
  std::thread thread_;
  Handlers handlers_;
  std::string path_;
  unsigned baud_ = 115200;
  std::atomic<bool> up_{false};
  std::atomic<bool> closing_{false};
  std::chrono::milliseconds reconnect_interval_{300};
  std::atomic<bool> will_reopen_{true};
  uint8_t read_buf_[4096] = {};
  std::deque<std::vector<uint8_t>> write_queue_;  // I/O thread only
  std::atomic<int64_t> last_write_ns_{0}, longest_write_gap_ns_{0};  // steady clock; set on the I/O thread
  std::atomic<unsigned> generation_{0};            // one per open(): stale writes are dropped
};

}  // namespace nlsoft::console
