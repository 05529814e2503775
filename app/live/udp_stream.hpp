#pragma once
// `--udp HOST:PORT`: every telemetry sample as one JSON object per UDP
// datagram, the layout PlotJuggler's UDP server reads with its JSON
// protocol (flat numeric fields, the time in seconds under "timestamp"), so
// engineers plot live in the tool they already use while the console
// records as before.
//
// The link thread only copies the sample into a bounded queue; a sender
// thread of its own formats and sends, so a slow network or a busy
// receiver never delays the link or the recording. A full queue drops the
// oldest samples and counts them (the stream is a view, the database is the
// record).
//
// The socket is connected to the target, so the kernel hands back the ICMP
// "port unreachable" a target with nobody listening answers with, as
// ECONNREFUSED on a later send: the stream says once that nothing is
// listening (and sends on: PlotJuggler may be started later).
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "app/record/sample.hpp"

namespace nlsoft::console {

// "HOST:PORT" -> (host, port); throws CliError in words.
std::pair<std::string, uint16_t> parse_udp_target(const std::string& text);

// One sample as the datagram's JSON text: timestamp (UNIX seconds at
// arrival), run (0 outside a run), step, y_ref_0.., y_hat_0.., y_true_0..,
// u_0.., cost, iterations, compute_us; fields the sample lacks, and
// non-finite values, are left out.
std::string sample_json(const Sample& s, double timestamp, int64_t run);

class UdpStream {
 public:
  using Notify = std::function<void(const std::string&)>;
  // Resolves the target at once, so a bad host fails before anything starts.
  // Throws CliError. `notify` hears, from the sender thread, that nobody
  // listens at the target (once).
  explicit UdpStream(const std::string& target, Notify notify = {}, size_t queue = 8192);
  // Sends the samples still queued, then stops and joins the sender thread.
  void finish();
  ~UdpStream();  // finish()
  UdpStream(const UdpStream&) = delete;
  UdpStream& operator=(const UdpStream&) = delete;

  // From the link thread: never blocks on the network.
  void push(const Sample& s, int64_t run);

  uint64_t sent() const { return sent_.load(); }
  uint64_t dropped() const { return dropped_.load(); }
  uint64_t refused() const { return refused_.load(); }  // sends the target refused (nobody listening)
  const std::string& target() const { return target_; }

 private:
  struct Item {
    Sample sample;
    double timestamp;
    int64_t run;
  };
  void loop();

  struct Socket;
  std::unique_ptr<Socket> socket_;
  std::string target_;
  size_t capacity_;
  std::mutex mu_;
  std::condition_variable cv_;
  std::deque<Item> queue_;
  bool stop_ = false;
  Notify notify_;
  std::atomic<uint64_t> sent_{0}, dropped_{0}, refused_{0};
  std::thread thread_;  // last: starts once everything above exists
};

}  // namespace nlsoft::console
