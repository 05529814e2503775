#pragma once
// One background thread for everything that waits on the firmware or the
// disk (parameter writes, uploads, runs, loading the runs list), so the UI
// keeps drawing at its own pace. Tasks run in order, one at a time, which
// is also what the stop-and-wait protocol wants.
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace nlsoft::console::tui {

class Worker {
 public:
  // Receives what a task let escape ("<task>: <what>"). Called on the
  // worker thread; the default writes to stderr.
  using Report = std::function<void(const std::string&)>;

  explicit Worker(Report report = {}) : report_(std::move(report)), thread_([this] { loop(); }) {}
  ~Worker() { stop(); }
  Worker(const Worker&) = delete;
  Worker& operator=(const Worker&) = delete;

  void post(std::string what, std::function<void()> task) {
    {
      std::lock_guard<std::mutex> lock(mu_);
      if (stop_) return;  // shutting down: nobody is left to run it
      tasks_.emplace_back(std::move(what), std::move(task));
    }
    cv_.notify_all();
  }
  // Lets the running task finish, drops the queued ones, joins the thread.
  // Idempotent. Whoever owns what the tasks touch calls this before
  // destroying it; a task still running is not interrupted, so the owner
  // first asks it to end (e.g. ScriptRunner::cancel).
  void stop() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
      tasks_.clear();
    }
    cv_.notify_all();
    if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
  }
  // What is running now and how many wait ("" when idle).
  std::string busy() const {
    std::lock_guard<std::mutex> lock(mu_);
    if (current_.empty()) return "";
    return tasks_.empty() ? current_ : current_ + " (+" + std::to_string(tasks_.size()) + " queued)";
  }

 private:
  void loop() {
    std::unique_lock<std::mutex> lock(mu_);
    while (true) {
      cv_.wait(lock, [this] { return stop_ || !tasks_.empty(); });
      if (stop_) return;
      auto [what, task] = std::move(tasks_.front());
      tasks_.pop_front();
      current_ = what;
      lock.unlock();
      // Tasks report their own errors; anything that still escapes must not
      // end the program (std::terminate) with the terminal in raw mode.
      std::string escaped;
      try {
        task();
      } catch (const std::exception& e) {
        escaped = what + ": " + e.what();
      } catch (...) {
        escaped = what + ": unknown error";
      }
      if (!escaped.empty()) report(escaped);
      lock.lock();
      current_.clear();
    }
  }
  void report(const std::string& text) noexcept {
    try {
      if (report_) report_(text);
      else std::fprintf(stderr, "nlsoft-console: %s\n", text.c_str());
    } catch (...) {
    }
  }

  Report report_;
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<std::pair<std::string, std::function<void()>>> tasks_;
  std::string current_;
  bool stop_ = false;
  std::thread thread_;  // last: starts once everything above exists
};

}  // namespace nlsoft::console::tui
