// `--udp HOST:PORT`: every telemetry sample reaches a UDP socket as one JSON
// object (PlotJuggler's UDP server, JSON protocol), while the run is
// recorded exactly as without it.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "host/files/cli_error.hpp"
#include "app/live/udp_stream.hpp"
#include "app/record/run_store.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

using test::run_process;
using test::shell_quote;

// A UDP socket on a free loopback port, received on a thread of its own so
// no datagram waits in (and overflows) the kernel's buffer.
class Receiver {
 public:
  Receiver() {
    fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    timeval tv{0, 100000};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    thread_ = std::thread([this] {
      while (!stop_) receive(0);
    });
  }
  ~Receiver() {
    finish();
    ::close(fd_);
  }
  // Once the sender has exited: every datagram it sent to loopback is in
  // the socket by then, so reading until none is left takes them all.
  void finish() {
    if (!thread_.joinable()) return;
    stop_ = true;
    thread_.join();
    while (receive(MSG_DONTWAIT)) {
    }
  }
  uint16_t port() const { return port_; }
  const std::vector<std::string>& datagrams() const { return datagrams_; }

 private:
  bool receive(int flags) {
    char buf[65536];
    const ssize_t n = ::recv(fd_, buf, sizeof buf, flags);
    if (n > 0) datagrams_.emplace_back(buf, size_t(n));
    return n > 0;
  }
  int fd_ = -1;
  uint16_t port_ = 0;
  std::atomic<bool> stop_{false};
  std::vector<std::string> datagrams_;
  std::thread thread_;
};

// "--udp TARGET: N samples sent, D dropped": the console's own count.
std::pair<long, long> said_sent_dropped(const std::string& output, const std::string& target) {
  const std::string tag = "--udp " + target + ": ";
  const size_t at = output.rfind(tag);
  long sent = -1, dropped = -1;
  if (at != std::string::npos)
    std::sscanf(output.c_str() + at + tag.size(), "%ld samples sent, %ld dropped", &sent, &dropped);
  return {sent, dropped};
}

TEST(UdpStream, EverySampleOfTheRunArrivesAsJsonAndTheRecordingIsUnchanged) {
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  test::TempDir dir;
  const std::string script = dir.file("run.nls"), db = dir.file("runs.db");
  std::ofstream(script) << "ref swirl\nrun 1s\nexpect lost == 0\n";
  Receiver rx;
  const std::string target = "127.0.0.1:" + std::to_string(rx.port());
  const auto r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " + shell_quote(db) + " --script " +
                             shell_quote(script) + " --udp " + target);
  rx.finish();
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("streaming every telemetry sample to 127.0.0.1:"), std::string::npos) << r.output;
  // What the console says it sent is what arrived; none dropped on its side.
  const auto [sent, dropped] = said_sent_dropped(r.output, target);
  EXPECT_EQ(dropped, 0) << r.output;
  EXPECT_EQ(sent, long(rx.datagrams().size())) << r.output;

  RunStore store(db);
  const auto runs = store.list();
  ASSERT_EQ(runs.size(), 1u);
  const RunSeries s = store.series(runs[0].id);
  ASSERT_GT(s.rows(), 100u);

  std::vector<nlohmann::json> in_run;
  double last_t = 0;
  for (const std::string& d : rx.datagrams()) {
    const auto j = nlohmann::json::parse(d, nullptr, false);
    ASSERT_FALSE(j.is_discarded()) << d;
    ASSERT_TRUE(j.is_object()) << d;
    ASSERT_TRUE(j.contains("timestamp") && j["timestamp"].is_number()) << d;
    EXPECT_GE(j["timestamp"].get<double>(), last_t) << "timestamps never go back";
    last_t = j["timestamp"].get<double>();
    if (j["run"].get<int64_t>() == runs[0].id) in_run.push_back(j);
  }
  // Every recorded sample was streamed, with the same values.
  ASSERT_EQ(in_run.size(), s.rows());
  for (size_t i = 0; i < s.rows(); i += 97) {
    const auto& j = in_run[i];
    EXPECT_EQ(j["step"].get<uint32_t>(), s.step[i]);
    for (int a = 0; a < 3; ++a) {
      EXPECT_FLOAT_EQ(j["y_ref_" + std::to_string(a)].get<float>(), s.y_ref[i * 3 + size_t(a)]);
      EXPECT_FLOAT_EQ(j["y_true_" + std::to_string(a)].get<float>(), s.y_true[i * 3 + size_t(a)]);
    }
    for (int u = 0; u < 6; ++u) EXPECT_FLOAT_EQ(j["u_" + std::to_string(u)].get<float>(), s.u[i * 6 + size_t(u)]);
    EXPECT_TRUE(j.contains("cost") && j.contains("iterations") && j.contains("compute_us")) << j.dump();
  }
}

TEST(UdpStream, ABadTargetIsRefusedBeforeAnythingStarts) {
  auto error_of = [](const std::string& t) {
    try {
      UdpStream u(t);
    } catch (const CliError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_of("localhost"), "--udp localhost: expected HOST:PORT, e.g. 127.0.0.1:9870");
  EXPECT_EQ(error_of("localhost:0"), "--udp localhost:0: the port must be a number 1..65535, not '0'");
  EXPECT_EQ(error_of("localhost:plot"), "--udp localhost:plot: the port must be a number 1..65535, not 'plot'");
  EXPECT_NE(error_of("no-such-host.invalid:9870").find("cannot resolve no-such-host.invalid"), std::string::npos);
  const std::string empty = ::testing::TempDir() + "udp-empty.nls";
  std::ofstream{empty};
  const auto r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --no-record --script " + empty +
                             " --udp x:99999");
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("the port must be a number 1..65535, not '99999'"), std::string::npos) << r.output;
}

// A loopback port nobody listens on: bound to find a free one, then closed.
uint16_t free_udp_port() {
  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  ::close(fd);
  return ntohs(a.sin_port);
}

size_t count(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t at = s.find(what); at != std::string::npos; at = s.find(what, at + 1)) ++n;
  return n;
}

// The kernel answers datagrams to a closed port with ICMP "port
// unreachable"; the console says once that nothing listens there, and the
// run is recorded as ever.
TEST(UdpStream, NobodyListeningIsSaidOnce) {
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  test::TempDir dir;
  const std::string script = dir.file("run.nls"), db = dir.file("runs.db");
  std::ofstream(script) << "run 1s\nexpect lost == 0\n";
  const std::string target = "127.0.0.1:" + std::to_string(free_udp_port());
  const auto r = run_process(std::string(NLSOFT_CONSOLE_BIN) + " --sim hasel --db " + shell_quote(db) + " --script " +
                             shell_quote(script) + " --udp " + target);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(count(r.output, "--udp " + target + ": nothing is listening there"), 1u) << r.output;
  RunStore store(db);
  ASSERT_EQ(store.list().size(), 1u);
  EXPECT_GT(store.list()[0].samples, 100u);
}

TEST(UdpStream, SampleJsonLeavesOutWhatTheSampleLacks) {
  Sample s;
  s.n = 2;
  s.m = 1;
  s.step = 7;
  s.mask = protocol::telemetry_field::kStep | protocol::telemetry_field::kYRef | protocol::telemetry_field::kU;
  s.y_ref()[0] = 1.5f;
  s.y_ref()[1] = std::numeric_limits<float>::quiet_NaN();
  s.u()[0] = 0.25f;
  EXPECT_EQ(sample_json(s, 12.5, 3), "{\"timestamp\":12.500000,\"run\":3,\"step\":7,\"y_ref_0\":1.5,\"u_0\":0.25}");
}

}  // namespace
}  // namespace nlsoft::console
