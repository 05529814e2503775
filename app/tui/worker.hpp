#pragma once
// One background thread for everything that waits on the firmware or the
// disk (parameter writes, uploads, runs, loading the runs list), so the UI
// keeps drawing at its own pace. Tasks run in order, one at a time, which
// is also what the stop-and-wait protocol wants.
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace nlsoft::console::tui {

class Worker {
 public:
  Worker() : thread_([this] { loop(); }) {}
  ~Worker() {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
  }
  void post(std::string what, std::function<void()> task) {
    {
      std::lock_guard<std::mutex> lock(mu_);
      tasks_.emplace_back(std::move(what), std::move(task));
    }
    cv_.notify_all();
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
      task();  // tasks report their own errors
      lock.lock();
      current_.clear();
    }
  }
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::deque<std::pair<std::string, std::function<void()>>> tasks_;
  std::string current_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace nlsoft::console::tui
