#pragma once
// Recording into SQLite without ever blocking the link: producers append to
// a bounded in-memory queue (a mutex held for a copy, never for I/O); one
// writer thread commits what has accumulated in a transaction every
// `batch_delay` or sooner when the queue is large. A crash loses at most the
// batch not yet committed; WAL keeps every commit. A full queue drops
// samples and records the gap, a failed write stops recording and says why:
// nothing is lost silently.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <variant>
#include <vector>

#include "app/record/sample.hpp"
#include "app/record/sqlite.hpp"
#include "app/record/utc_time.hpp"

namespace nlsoft::console {

struct RunInfo {
  std::string label, notes, platform, firmware;
  uint32_t model_hash = 0, param_hash = 0;
  double loop_rate_hz = 0;
  int n = 0, m = 0, decimation = 1;
  std::string reference;  // JSON
  std::vector<std::pair<std::string, std::string>> params;  // name, value at start
  std::string kind = "control";  // "ident": an identification run
  int w = 0;                     // sensors each sample keeps (identification runs)
  std::string excitation;        // JSON, identification runs
};

// Default database: $XDG_DATA_HOME/nlsoft/runs.db (an absolute
// XDG_DATA_HOME), else $HOME/.local/share/nlsoft/runs.db; throws CliError
// when HOME is unset, relative or not an existing folder.
std::string default_db_path();
// Creates the directory of `path` if missing; throws DbError if it cannot.
void ensure_parent_dir(const std::string& path);


class Recorder {
 public:
  struct Options {
    size_t queue_capacity = 1u << 17;  // ~13 s at 10 kHz
    std::chrono::milliseconds batch_delay{50};
    size_t batch_wakeup = 8192;  // commit early once this many items wait
    // Another process holding the write lock (a colleague's sqlite3 shell)
    // stalls a commit: it is retried, the samples waiting in the queue (up
    // to queue_capacity, beyond it counted lost as a gap) for this long. A
    // lock held longer: what waits is given up and counted lost, and so is
    // every sample until the lock goes, so memory stays bounded however long
    // it lasts; then one gap per run says how many and for how long the
    // database was locked, and recording goes on.
    std::chrono::milliseconds busy_limit{30000};
    // Asked while a write waits on a lock past busy_limit: true gives up
    // (the console's Ctrl-C), as a failed write would.
    std::function<bool()> give_up;
  };

  // Opens or creates the database and migrates it. Throws DbError.
  explicit Recorder(const std::string& path) : Recorder(path, Options{}) {}
  Recorder(const std::string& path, Options options);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Synchronous (waits for the writer): returns the new run's id.
  int64_t begin_run(const RunInfo& info);
  // Synchronous: everything queued before is committed, then the run closes.
  void end_run(int64_t run_id, const std::string& reason, uint64_t samples, uint64_t lost_frames);

  // Never block on I/O. add_sample returns false when the queue is full (the
  // drop is counted and recorded as a gap once there is room again).
  bool add_sample(int64_t run_id, const Sample& s);
  void add_param_change(int64_t run_id, double t, const std::string& name, const std::string& value);
  // duration_s < 0: not known.
  void add_gap(int64_t run_id, uint64_t after_k, uint64_t lost_frames, const std::string& reason,
               double duration_s = -1);
  void add_link_event(int64_t run_id, const std::string& kind, const std::string& detail);
  // Protocol 1.4: the sensor channels invalid at a step and the samples' age.
  void add_sensor_health(int64_t run_id, uint32_t step, uint32_t invalid, uint16_t age_ms);
  void set_notes(int64_t run_id, const std::string& notes);

  // Waits until everything queued so far is committed. Throws DbError if the
  // writer has failed.
  void flush();

  // First write error ("" if none). After an error nothing more is written.
  std::string error() const;
  uint64_t dropped_samples() const { return dropped_total_.load(); }
  uint64_t committed_samples() const { return committed_.load(); }
  // True while another process's lock has outlasted busy_limit: samples are
  // being counted lost, not kept.
  bool locked_out() const { return locked_out_.load(); }
  // The samples of a run this recorder could not save (a full queue, a
  // database locked past busy_limit) and the last reason.
  struct Loss {
    uint64_t samples = 0;
    std::string reason;
  };
  Loss loss(int64_t run_id) const;
  const std::string& path() const { return path_; }

 private:
  struct SampleItem {
    int64_t run;
    Sample s;
  };
  struct TextItem {
    enum Kind { Param, Gap, Event, Notes, Health } kind;
    int64_t run;
    double t;
    int64_t a, b;
    std::string x, y;
  };
  struct SyncItem {
    std::shared_ptr<std::promise<int64_t>> done;
    std::shared_ptr<RunInfo> begin;  // null: a flush or an end
    int64_t end_run = 0;
    std::string end_reason;
    uint64_t samples = 0, lost = 0;
  };
  using Item = std::variant<SampleItem, TextItem, SyncItem>;

  void push(Item item);
  int64_t sync(SyncItem item);
  void writer();
  void checkpointer();
  void write_batch(std::vector<Item>& batch, std::vector<std::shared_ptr<std::promise<int64_t>>>& waiting);
  // The parts of a batch's transaction, and what a failed batch leaves.
  size_t write_samples(const std::vector<Item>& batch, size_t first);
  void write_text(const TextItem& ti, const std::string& now);
  int64_t write_sync(const SyncItem& sy, const std::string& now, std::vector<int64_t>& begun,
                     std::vector<int64_t>& ended);
  void check_runs_exist(const std::vector<int64_t>& runs);
  void fail_batch(std::vector<Item>& batch, const std::string& failed);
  bool wait_out_lock(std::vector<Item>& batch, std::vector<int64_t>& sample_runs,
                     std::optional<std::chrono::steady_clock::time_point>& stalled_since,
                     std::chrono::steady_clock::time_point attempt_started);

  std::string path_;
  Options options_;
  std::unique_ptr<Db> db_;
  std::unique_ptr<Db> checkpoint_db_;
  Stmt insert_sample_, insert_samples_, insert_param_, insert_gap_, insert_event_, insert_health_, insert_run_, end_run_, set_notes_,
      run_exists_, heartbeat_;
  // The runs this recorder has begun and not ended (writer thread only):
  // their heartbeat_at is renewed every kHeartbeatPeriod, so `runs delete`
  // in another process sees they are being recorded (run_edit.hpp).
  std::vector<int64_t> open_runs_;
  std::chrono::steady_clock::time_point last_heartbeat_{};
  bool heartbeat_due_now() const;

  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::vector<Item> queue_;
  bool stop_ = false;
  bool urgent_ = false;
  std::string error_;
  // Samples given up to a lock, per run, until the lock goes and their gap
  // is written.
  struct LockLoss {
    int64_t run = 0;
    uint64_t first_k = 0, count = 0;
    uint32_t first_us = 0, last_us = 0;
    bool timed = false;
  };
  void lose_to_lock(int64_t run, const Sample& s);  // mu_ held
  void lose_unwritten(int64_t run, uint64_t samples);  // mu_ held, error_ set
  void write_end(const SyncItem& end, const std::string& now);  // in a transaction
  void close_after_failure(const SyncItem& end);
  void give_up_waiting_samples(std::vector<Item>& batch);  // mu_ held
  void write_lock_gaps(double locked_s);
  std::vector<LockLoss> lock_losses_;
  std::map<int64_t, Loss> losses_;  // every run's, kept for its end and the console's summary
  std::atomic<bool> locked_out_{false};
  uint64_t overflow_ = 0;  // samples dropped since the last recorded gap
  uint64_t overflow_after_k_ = 0;
  int64_t overflow_run_ = 0;
  std::atomic<uint64_t> dropped_total_{0};
  std::atomic<uint64_t> committed_{0};
  std::thread thread_;
  std::condition_variable checkpoint_cv_;
  static constexpr int kCheckpointFrames = 64;  // log pages (4 kB) that wake the checkpointer early
  std::thread checkpointer_;
};

}  // namespace nlsoft::console
