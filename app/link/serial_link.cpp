#include "app/link/serial_link.hpp"
#include "app/link/steady_ns.hpp"

#include <algorithm>
#include <boost/asio/post.hpp>
#include <boost/asio/write.hpp>
#include <fmt/format.h>
#include <sys/ioctl.h>

#include "app/link/custom_baud.hpp"
#include "app/link/link_error.hpp"
#include "app/link/port_check.hpp"

namespace nlsoft::console {

namespace asio = boost::asio;

SerialLink::SerialLink() : port_(io_), reopen_timer_(io_) {}

SerialLink::~SerialLink() { close(); }

std::string SerialLink::open_port() {
  boost::system::error_code ec;
  port_.open(path_, ec);
  if (ec == boost::system::errc::inappropriate_io_control_operation) return check_terminal(-1, path_);
  if (ec) return fmt::format("cannot open {}: {}", path_, ec.message());
  const int fd = port_.native_handle();
  std::string why = check_terminal(fd, path_);
  if (why.empty()) why = take_exclusive(fd, path_);
  if (why.empty()) {
    why = check_no_other_reader(fd, path_);
    // The exclusive mode outlives this open while anyone holds the port:
    // it must not lock out the next try once the other reader is gone.
    if (!why.empty()) ioctl(fd, TIOCNXCL);
  }
  if (why.empty()) {
    using sp = asio::serial_port_base;
    port_.set_option(sp::character_size(8), ec);
    if (!ec) port_.set_option(sp::parity(sp::parity::none), ec);
    if (!ec) port_.set_option(sp::stop_bits(sp::stop_bits::one), ec);
    if (!ec) port_.set_option(sp::flow_control(sp::flow_control::none), ec);
    if (ec && !is_pseudo_terminal(fd)) why = fmt::format("cannot set 8N1 without flow control on {}: {}", path_, ec.message());
  }
  if (why.empty()) {
    port_.set_option(asio::serial_port_base::baud_rate(baud_), ec);
    if (ec && !set_custom_baud(fd, baud_).empty()) why = fmt::format("cannot set {} baud on {}", baud_, path_);
  }
  if (!why.empty()) {
    boost::system::error_code ignore;
    port_.close(ignore);
  }
  return why;
}

void SerialLink::open(const std::string& path, unsigned baud, Handlers handlers) {
  close();
  closing_ = false;
  path_ = path;
  baud_ = baud;
  will_reopen_ = true;
  handlers_ = std::move(handlers);
  io_.restart();
  ++generation_;  // writes posted while closed (still queued in io_) never reach this port
  const std::string why = open_port();
  if (!why.empty()) throw LinkError(why);
  up_ = true;
  // A leading delimiter ends whatever partial frame the firmware holds.
  write_queue_.push_back({0x00});
  start_write();
  start_read();
  thread_ = std::thread([this] {
    auto guard = asio::make_work_guard(io_);
    io_.run();
  });
}

void SerialLink::close() {
  if (!thread_.joinable()) return;
  closing_ = true;
  asio::post(io_, [this] {
    boost::system::error_code ignore;
    reopen_timer_.cancel();
    port_.close(ignore);
    io_.stop();
  });
  thread_.join();
  up_ = false;
  write_queue_.clear();
}

void SerialLink::write(std::vector<uint8_t> bytes) {
  asio::post(io_, [this, g = generation_.load(), b = std::move(bytes)]() mutable {
    if (!up_ || g != generation_.load()) return;
    const bool idle = write_queue_.empty();
    write_queue_.push_back(std::move(b));
    if (idle) start_write();
  });
}

std::chrono::milliseconds SerialLink::take_longest_write_gap() {
  const int64_t now = now_ns();
  const int64_t last = last_write_ns_.load();
  const int64_t longest = std::max(longest_write_gap_ns_.exchange(0), last != 0 ? now - last : 0);
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::nanoseconds(longest));
}

void SerialLink::start_write() {
  if (write_queue_.empty() || !port_.is_open()) return;
  asio::async_write(port_, asio::buffer(write_queue_.front()),
                    [this](const boost::system::error_code& ec, size_t) {
                      if (ec) {
                        if (ec != asio::error::operation_aborted) port_failed("write: " + ec.message());
                        return;
                      }
                      const int64_t now = now_ns();
                      const int64_t before = last_write_ns_.exchange(now);
                      if (before != 0 && now - before > longest_write_gap_ns_.load()) longest_write_gap_ns_ = now - before;
                      if (!write_queue_.empty()) write_queue_.pop_front();
                      start_write();
                    });
}

void SerialLink::start_read() {
  port_.async_read_some(asio::buffer(read_buf_), [this](const boost::system::error_code& ec, size_t n) {
    if (ec) {
      if (ec != asio::error::operation_aborted) port_failed(ec.message());
      return;
    }
    if (handlers_.on_bytes) handlers_.on_bytes(read_buf_, n);
    start_read();
  });
}

void SerialLink::port_failed(const std::string& why) {
  if (closing_ || !up_) return;
  up_ = false;
  boost::system::error_code ignore;
  port_.close(ignore);
  write_queue_.clear();
  const bool pty_by_number = path_.rfind("/dev/pts/", 0) == 0;
  will_reopen_ = !pty_by_number;
  if (handlers_.on_down)
    handlers_.on_down(pty_by_number ? why + "; a pseudo-terminal does not come back, so it is not reopened" : why);
  if (!pty_by_number) schedule_reopen();
}

void SerialLink::schedule_reopen() {
  if (closing_) return;
  reopen_timer_.expires_after(reconnect_interval_);
  reopen_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || closing_) return;
    if (!open_port().empty()) return schedule_reopen();
    up_ = true;
    write_queue_.push_back({0x00});
    start_write();
    start_read();
    if (handlers_.on_up) handlers_.on_up();
  });
}

}  // namespace nlsoft::console
