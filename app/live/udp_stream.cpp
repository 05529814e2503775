#include "app/live/udp_stream.hpp"

#include <fmt/format.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <chrono>
#include <cmath>
#include <cstdlib>

#include "host/files/cli_error.hpp"

namespace nlsoft::console {

using host::CliError;

namespace tf = protocol::telemetry_field;
namespace ip = boost::asio::ip;

struct UdpStream::Socket {
  boost::asio::io_context io;
  ip::udp::socket socket{io};
  ip::udp::endpoint to;
};

std::pair<std::string, uint16_t> parse_udp_target(const std::string& text) {
  const size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size())
    throw CliError(fmt::format("--udp {}: expected HOST:PORT, e.g. 127.0.0.1:9870", text));
  std::string host = text.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);  // [::1]
  const std::string port = text.substr(colon + 1);
  char* end = nullptr;
  const long p = std::strtol(port.c_str(), &end, 10);
  if (*end != '\0' || p < 1 || p > 65535)
    throw CliError(fmt::format("--udp {}: the port must be a number 1..65535, not '{}'", text, port));
  return {host, uint16_t(p)};
}

std::string sample_json(const Sample& s, double timestamp, int64_t run) {
  std::string j = fmt::format("{{\"timestamp\":{:.6f},\"run\":{},\"step\":{}", timestamp, run, s.step);
  auto field = [&](const char* name, int i, float v) {
    if (std::isfinite(v)) j += fmt::format(",\"{}_{}\":{}", name, i, v);  // shortest text that reads back the same float
  };
  if (s.has(tf::kYRef))
    for (int i = 0; i < s.n; ++i) field("y_ref", i, s.y_ref()[i]);
  if (s.has(tf::kYHat))
    for (int i = 0; i < s.n; ++i) field("y_hat", i, s.y_hat()[i]);
  if (s.has(tf::kYTrue))
    for (int i = 0; i < s.n; ++i) field("y_true", i, s.y_true()[i]);
  if (s.has(tf::kU))
    for (int i = 0; i < s.m; ++i) field("u", i, s.u()[i]);
  if (s.has(tf::kCost) && std::isfinite(s.cost)) j += fmt::format(",\"cost\":{}", s.cost);
  if (s.has(tf::kSolver)) j += fmt::format(",\"iterations\":{},\"compute_us\":{}", s.iterations, s.compute_us);
  return j + "}";
}

UdpStream::UdpStream(const std::string& target, Notify notify, size_t queue)
    : socket_(std::make_unique<Socket>()), target_(target), capacity_(queue ? queue : 1), notify_(std::move(notify)) {
  const auto [host, port] = parse_udp_target(target);
  boost::system::error_code ec;
  ip::udp::resolver resolver(socket_->io);
  const auto found = resolver.resolve(host, std::to_string(port), ec);
  if (ec || found.empty()) throw CliError(fmt::format("--udp {}: cannot resolve {}: {}", target, host, ec.message()));
  socket_->to = *found.begin();
  socket_->socket.open(socket_->to.protocol(), ec);
  if (ec) throw CliError(fmt::format("--udp {}: cannot open a UDP socket: {}", target, ec.message()));
  // Connected, a UDP socket is told of ICMP errors from its peer.
  socket_->socket.connect(socket_->to, ec);
  if (ec) throw CliError(fmt::format("--udp {}: cannot send to {}: {}", target, host, ec.message()));
  thread_ = std::thread([this] { loop(); });
}

UdpStream::~UdpStream() { finish(); }

void UdpStream::finish() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void UdpStream::push(const Sample& s, int64_t run) {
  const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (queue_.size() >= capacity_) {
      queue_.pop_front();
      ++dropped_;
    }
    queue_.push_back({s, now, run});
  }
  cv_.notify_one();
}

void UdpStream::loop() {
  std::unique_lock<std::mutex> lock(mu_);
  while (true) {
    cv_.wait(lock, [this] { return stop_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopped, and every sample sent
    const Item item = queue_.front();
    queue_.pop_front();
    lock.unlock();
    const std::string text = sample_json(item.sample, item.timestamp, item.run);
    boost::system::error_code ec;
    // Nobody listening (ICMP port unreachable) shows up as ECONNREFUSED on
    // the next send, which is itself not sent: a view with no viewer, not
    // a fault, said once.
    socket_->socket.send(boost::asio::buffer(text), 0, ec);
    if (ec == boost::asio::error::connection_refused) {
      if (refused_++ == 0 && notify_)
        notify_(fmt::format("--udp {}: nothing is listening there (the port is closed); sending on, so a plotter "
                            "started now still gets the samples",
                            target_));
    } else if (!ec) {
      ++sent_;
    }
    lock.lock();
  }
}

}  // namespace nlsoft::console
