#include "app/record/recorder.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <ctime>

#include "host/files/cli_error.hpp"
#include "app/record/lock_gap.hpp"
#include "app/record/recorder_mark.hpp"
#include "app/record/schema.hpp"

namespace nlsoft::console {

using host::CliError;

namespace tf = protocol::telemetry_field;

namespace {

// Rows per multi-row INSERT: one statement step for many samples amortises
// SQLite's per-statement cost (measured +25-30 % rows/s at 32).
constexpr size_t kSamplesPerInsert = 32;
constexpr int kSampleColumns = 11;

std::string sample_insert_sql(size_t rows) {
  std::string sql = "INSERT INTO samples(id,step,time_us,y_ref,y_hat,y_true,u,cost,iterations,compute_us,l) VALUES";
  for (size_t r = 0; r < rows; ++r) sql += r ? ",(?,?,?,?,?,?,?,?,?,?,?)" : "(?,?,?,?,?,?,?,?,?,?,?)";
  return sql;
}

// Binds one sample at parameter offset base (0 for the first row). The
// blobs point into s, which must outlive the statement's step.
void bind_sample(Stmt& st, int base, int64_t run, const Sample& s) {
  st.bind(base + 1, sample_key(run, s.k));
  if (s.has(tf::kStep)) st.bind(base + 2, int64_t(s.step)); else st.bind_null(base + 2);
  if (s.has(tf::kTime)) st.bind(base + 3, int64_t(s.time_us)); else st.bind_null(base + 3);
  const size_t nb = size_t(s.n) * 4;
  if (s.has(tf::kYRef)) st.bind_blob(base + 4, s.y_ref(), nb); else st.bind_null(base + 4);
  if (s.has(tf::kYHat)) st.bind_blob(base + 5, s.y_hat(), nb); else st.bind_null(base + 5);
  if (s.has(tf::kYTrue)) st.bind_blob(base + 6, s.y_true(), nb); else st.bind_null(base + 6);
  if (s.has(tf::kU)) st.bind_blob(base + 7, s.u(), size_t(s.m) * 4); else st.bind_null(base + 7);
  if (s.has(tf::kCost)) st.bind(base + 8, double(s.cost)); else st.bind_null(base + 8);
  if (s.has(tf::kSolver)) {
    st.bind(base + 9, int64_t(s.iterations));
    st.bind(base + 10, double(s.compute_us));
  } else {
    st.bind_null(base + 9);
    st.bind_null(base + 10);
  }
  if (s.w > 0) st.bind_blob(base + 11, s.l, size_t(s.w) * 4); else st.bind_null(base + 11);
}

}  // namespace

std::string default_db_path() {
  // The XDG rules: $XDG_DATA_HOME when it is an absolute path (a relative
  // one is ignored), else $HOME/.local/share. A home that is not there is
  // refused rather than made (as /nonexistent/.local/... at the root, or
  // ./.local/... of whatever folder the console was started in).
  if (const char* x = std::getenv("XDG_DATA_HOME"); x && *x == '/') return std::string(x) + "/nlsoft/runs.db";
  const char* home = std::getenv("HOME");
  const std::string fix = "set XDG_DATA_HOME or HOME to a folder, or give --db FILE";
  if (!home || !*home) throw CliError("no folder for the recording database: HOME is not set; " + fix);
  struct stat st {};
  if (*home != '/')
    throw CliError(
        fmt::format("no folder for the recording database: HOME={} is not an absolute path; {}", home, fix));
  const bool there = ::stat(home, &st) == 0;
  if (!there || !S_ISDIR(st.st_mode))
    throw CliError(fmt::format("no folder for the recording database: HOME={} {}; {}", home,
                               there ? "is not a folder" : "does not exist", fix));
  return std::string(home) + "/.local/share/nlsoft/runs.db";
}

void ensure_parent_dir(const std::string& path) {
  const size_t slash = path.rfind('/');
  if (slash == std::string::npos || slash == 0) return;
  const std::string dir = path.substr(0, slash);
  for (size_t pos = 1; pos <= dir.size(); ++pos) {
    if (pos != dir.size() && dir[pos] != '/') continue;
    const std::string part = dir.substr(0, pos);
    if (::mkdir(part.c_str(), 0755) != 0 && errno != EEXIST)
      throw DbError(fmt::format("cannot create directory {} for the database: {}", part, std::strerror(errno)),
                    SQLITE_CANTOPEN);
  }
}

Recorder::Recorder(const std::string& path, Options options) : path_(path), options_(options) {
  ensure_parent_dir(path);
  db_ = std::make_unique<Db>(path, true);
  migrate(*db_);
  // Probe for a writer lock now, so "locked by another process" is said at
  // start instead of failing the first batch mid-run.
  db_->exec("BEGIN IMMEDIATE");
  db_->exec("ROLLBACK");
  insert_sample_ = db_->prepare(sample_insert_sql(1).c_str());
  insert_samples_ = db_->prepare(sample_insert_sql(kSamplesPerInsert).c_str());
  insert_param_ = db_->prepare("INSERT INTO params(run_id,t,at_start,name,value) VALUES(?,?,?,?,?)");
  insert_gap_ = db_->prepare("INSERT INTO gaps(run_id,t,after_k,lost_frames,reason,duration_s) VALUES(?,?,?,?,?,?)");
  insert_event_ = db_->prepare("INSERT INTO link_events(t,run_id,kind,detail) VALUES(?,?,?,?)");
  insert_health_ = db_->prepare("INSERT INTO sensor_health(run_id,step,invalid,age_ms) VALUES(?,?,?,?)");
  insert_run_ = db_->prepare(
      "INSERT INTO runs(started_at,label,notes,platform,firmware,model_hash,param_hash,loop_rate_hz,n,m,"
      "decimation,reference,recorder_pid,recorder_host,heartbeat_at,kind,w,excitation) "
      "VALUES(?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
  end_run_ = db_->prepare(
      "UPDATE runs SET ended_at=?, end_reason=?, samples=?, lost_frames=?, recorder_pid=NULL, recorder_host=NULL, "
      "heartbeat_at=NULL WHERE id=?");
  heartbeat_ = db_->prepare("UPDATE runs SET heartbeat_at=? WHERE id=?");
  set_notes_ = db_->prepare("UPDATE runs SET notes=? WHERE id=?");
  run_exists_ = db_->prepare("SELECT 1 FROM runs WHERE id=?");
  // Checkpoints (copying the WAL into the database, with an fsync) would
  // stall the writer on the disk every few MB; a second connection does
  // them in the background instead, which WAL allows concurrently.
  db_->exec("PRAGMA wal_autocheckpoint=0");
  // ...and sooner than every 500 ms once the log passes 256 kB, so the log
  // stays small on a loaded machine too: a database that cannot grow is
  // found by the checkpoint while the log still has room for a run's close.
  sqlite3_wal_hook(
      db_->handle(),
      [](void* self, sqlite3*, const char*, int frames) {
        if (frames >= kCheckpointFrames) static_cast<Recorder*>(self)->checkpoint_cv_.notify_one();
        return SQLITE_OK;
      },
      this);
  checkpoint_db_ = std::make_unique<Db>(path, false);
  queue_.reserve(options_.batch_wakeup * 2);
  thread_ = std::thread([this] { writer(); });
  checkpointer_ = std::thread([this] { checkpointer(); });
}

void Recorder::checkpointer() {
  std::unique_lock<std::mutex> lock(mu_);
  while (!stop_) {
    checkpoint_cv_.wait_for(lock, std::chrono::milliseconds(500));
    if (stop_) break;
    lock.unlock();
    // PASSIVE never waits for the writer; a busy result just means "later".
    const int rc =
        sqlite3_wal_checkpoint_v2(checkpoint_db_->handle(), nullptr, SQLITE_CHECKPOINT_PASSIVE, nullptr, nullptr);
    lock.lock();
    // Any other failure is the database file refusing to grow (disk full,
    // a file-size limit). Recording stops now, while the log still has room
    // for the run's close: left to fill up, the log would fail the next
    // commit with no room left for anything, the close included.
    const int primary = rc & 0xFF;
    if (primary != SQLITE_OK && primary != SQLITE_BUSY && primary != SQLITE_LOCKED && error_.empty()) {
      error_ = db_error_words(path_, rc, nullptr);
      cv_.notify_all();
    }
  }
}

Recorder::~Recorder() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
  }
  cv_.notify_all();
  checkpoint_cv_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (checkpointer_.joinable()) checkpointer_.join();
  checkpoint_db_.reset();
  // Runs left open (the console leaving without ending them) are no longer
  // being recorded: their mark goes, so `runs delete` needs only --force.
  if (db_)
    for (int64_t run : open_runs_) {
      try {
        Stmt clear = db_->prepare("UPDATE runs SET recorder_pid=NULL, recorder_host=NULL, heartbeat_at=NULL WHERE id=?");
        clear.bind(1, run).exec();
      } catch (const DbError&) {
        // Locked or failed: the mark goes stale in kHeartbeatStaleS all the same.
      }
    }
  // Fold the WAL back so the file is self-contained when we are done.
  if (db_) sqlite3_wal_checkpoint_v2(db_->handle(), nullptr, SQLITE_CHECKPOINT_TRUNCATE, nullptr, nullptr);
}

void Recorder::push(Item item) {
  bool wake = false;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (!error_.empty()) return;
    queue_.push_back(std::move(item));
    wake = queue_.size() >= options_.batch_wakeup;
  }
  if (wake) cv_.notify_one();
}

bool Recorder::add_sample(int64_t run_id, const Sample& s) {
  bool wake = false;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (!error_.empty()) {
      lose_unwritten(run_id, 1);
      return false;
    }
    if (locked_out_.load()) {
      lose_to_lock(run_id, s);
      return false;
    }
    if (queue_.size() >= options_.queue_capacity) {
      Loss& loss = losses_[run_id];
      ++loss.samples;
      loss.reason = "recorder queue full: samples dropped";
      if (overflow_ == 0) overflow_after_k_ = s.k == 0 ? 0 : s.k - 1, overflow_run_ = run_id;
      ++overflow_;
      dropped_total_++;
      return false;
    }
    if (overflow_ > 0) {
      queue_.push_back(TextItem{TextItem::Gap, overflow_run_, -1, int64_t(overflow_after_k_), int64_t(overflow_),
                                "recorder queue full: samples dropped", {}});
      overflow_ = 0;
    }
    queue_.push_back(SampleItem{run_id, s});
    wake = queue_.size() >= options_.batch_wakeup;
  }
  if (wake) cv_.notify_one();
  return true;
}

void Recorder::add_param_change(int64_t run_id, double t, const std::string& name, const std::string& value) {
  push(TextItem{TextItem::Param, run_id, t, 0, 0, name, value});
}

void Recorder::add_sensor_health(int64_t run_id, uint32_t step, uint32_t invalid, uint16_t age_ms) {
  push(TextItem{TextItem::Health, run_id, double(age_ms), int64_t(step), int64_t(invalid), {}, {}});
}

void Recorder::add_gap(int64_t run_id, uint64_t after_k, uint64_t lost_frames, const std::string& reason,
                       double duration_s) {
  push(TextItem{TextItem::Gap, run_id, duration_s, int64_t(after_k), int64_t(lost_frames), reason, {}});
}

void Recorder::add_link_event(int64_t run_id, const std::string& kind, const std::string& detail) {
  push(TextItem{TextItem::Event, run_id, 0, 0, 0, kind, detail});
}

void Recorder::set_notes(int64_t run_id, const std::string& notes) {
  push(TextItem{TextItem::Notes, run_id, 0, 0, 0, notes, {}});
}

int64_t Recorder::sync(SyncItem item) {
  auto done = std::make_shared<std::promise<int64_t>>();
  auto fut = done->get_future();
  item.done = done;
  {
    std::lock_guard<std::mutex> lock(mu_);
    // A run's end is still tried after a failed write (close_after_failure).
    if (!error_.empty() && item.end_run == 0) throw DbError("recording stopped: " + error_, SQLITE_ERROR);
    queue_.push_back(std::move(item));
    urgent_ = true;
  }
  cv_.notify_one();
  return fut.get();  // rethrows the writer's DbError
}

int64_t Recorder::begin_run(const RunInfo& info) {
  SyncItem s;
  s.begin = std::make_shared<RunInfo>(info);
  return sync(std::move(s));
}

void Recorder::end_run(int64_t run_id, const std::string& reason, uint64_t samples, uint64_t lost_frames) {
  SyncItem s;
  s.end_run = run_id;
  s.end_reason = reason;
  s.samples = samples;
  s.lost = lost_frames;
  sync(std::move(s));
}

void Recorder::flush() { sync(SyncItem{}); }

Recorder::Loss Recorder::loss(int64_t run_id) const {
  std::lock_guard<std::mutex> lock(mu_);
  const auto it = losses_.find(run_id);
  return it == losses_.end() ? Loss{} : it->second;
}

void Recorder::lose_unwritten(int64_t run, uint64_t samples) {
  Loss& loss = losses_[run];
  loss.samples += samples;
  loss.reason = "not written: " + error_;
  dropped_total_ += samples;
}

void Recorder::close_after_failure(const SyncItem& end) {
  // The log's pages copied into the database, so the close is written at
  // the start of the log, over pages already copied, needing no new room.
  // The background checkpointer may hold the checkpoint lock at this
  // moment (SQLITE_BUSY at once: measured in 3 of 30 runs of a disk-full
  // run on a loaded machine, the close then failing for want of room):
  // wait for it, up to 2 s.
  for (int tries = 0; tries < 400; ++tries) {
    const int rc = sqlite3_wal_checkpoint_v2(db_->handle(), nullptr, SQLITE_CHECKPOINT_RESTART, nullptr, nullptr);
    if ((rc & 0xFF) != SQLITE_BUSY && (rc & 0xFF) != SQLITE_LOCKED) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  try {
    db_->exec("BEGIN");
    write_end(end, utc_now());
    db_->exec("COMMIT");
    open_runs_.erase(std::remove(open_runs_.begin(), open_runs_.end(), end.end_run), open_runs_.end());
    end.done->set_value(0);
  } catch (const DbError& e) {
    sqlite3_exec(db_->handle(), "ROLLBACK", nullptr, nullptr, nullptr);
    end.done->set_exception(std::make_exception_ptr(
        DbError(fmt::format("recording stopped: {}; closing run {} failed too: {}", error(), end.end_run, e.what()),
                SQLITE_ERROR)));
  }
}

void Recorder::write_end(const SyncItem& end, const std::string& now) {
  // The samples this recorder could not save are the run's losses too:
  // the caller counts what arrived.
  const uint64_t unsaved = loss(end.end_run).samples;
  end_run_.bind(1, now).bind(2, end.end_reason)
      .bind(3, int64_t(end.samples - std::min(unsaved, end.samples))).bind(4, int64_t(end.lost + unsaved))
      .bind(5, end.end_run).exec();
}

void Recorder::lose_to_lock(int64_t run, const Sample& s) {
  if (lock_losses_.empty() || lock_losses_.back().run != run) {
    LockLoss l;
    l.run = run;
    l.first_k = s.k;
    l.first_us = s.time_us;
    l.timed = s.has(tf::kTime);
    lock_losses_.push_back(l);
  }
  LockLoss& l = lock_losses_.back();
  ++l.count;
  l.last_us = s.time_us;
  ++losses_[run].samples;
  dropped_total_++;
}

void Recorder::give_up_waiting_samples(std::vector<Item>& items) {
  for (const Item& item : items)
    if (const auto* si = std::get_if<SampleItem>(&item)) lose_to_lock(si->run, si->s);
  items.erase(std::remove_if(items.begin(), items.end(),
                             [](const Item& item) { return std::holds_alternative<SampleItem>(item); }),
              items.end());
}

// After the lock: one gap per run for what was given up, with the time its
// samples span (the firmware's clock) and how long the lock lasted. Written
// at once, so the end of a run waiting in the same batch is read back with
// it; if that write fails too, the gaps wait in the queue like any other.
void Recorder::write_lock_gaps(double locked_s) {
  std::vector<LockLoss> gaps;
  {
    std::lock_guard<std::mutex> lock(mu_);
    gaps.swap(lock_losses_);
    locked_out_ = false;
    for (const LockLoss& g : gaps)
      losses_[g.run].reason = lock_gap_reason(locked_s);
  }
  if (gaps.empty()) return;
  const std::string reason = lock_gap_reason(locked_s);
  auto duration = [&](const LockLoss& g) {
    return g.timed && g.count > 1 ? double(uint32_t(g.last_us - g.first_us)) * 1e-6 : locked_s;
  };
  try {
    db_->exec("BEGIN");
    const std::string now = utc_now();
    for (const LockLoss& g : gaps)
      insert_gap_.bind(1, g.run).bind(2, now).bind(3, int64_t(g.first_k == 0 ? 0 : g.first_k - 1))
          .bind(4, int64_t(g.count)).bind(5, reason).bind(6, duration(g)).exec();
    db_->exec("COMMIT");
  } catch (const DbError&) {
    sqlite3_exec(db_->handle(), "ROLLBACK", nullptr, nullptr, nullptr);
    std::lock_guard<std::mutex> lock(mu_);
    for (const LockLoss& g : gaps)
      queue_.push_back(TextItem{TextItem::Gap, g.run, duration(g), int64_t(g.first_k == 0 ? 0 : g.first_k - 1),
                                int64_t(g.count), reason, {}});
  }
}

std::string Recorder::error() const {
  std::lock_guard<std::mutex> lock(mu_);
  return error_;
}

bool Recorder::heartbeat_due_now() const {
  return !open_runs_.empty() && std::chrono::steady_clock::now() - last_heartbeat_ >= kHeartbeatPeriod;
}

void Recorder::writer() {
  std::vector<Item> batch;
  batch.reserve(options_.batch_wakeup * 2);
  std::vector<std::shared_ptr<std::promise<int64_t>>> waiting;
  std::unique_lock<std::mutex> lock(mu_);
  while (true) {
    cv_.wait_for(lock, options_.batch_delay,
                 [this] { return stop_ || urgent_ || queue_.size() >= options_.batch_wakeup; });
    urgent_ = false;
    batch.swap(queue_);
    const bool stopping = stop_;
    lock.unlock();
    if (!batch.empty() || heartbeat_due_now()) write_batch(batch, waiting);
    batch.clear();
    lock.lock();
    if (stopping && queue_.empty()) break;
  }
}

void Recorder::write_batch(std::vector<Item>& batch, std::vector<std::shared_ptr<std::promise<int64_t>>>& waiting) {
  std::string failed;
  {
    std::lock_guard<std::mutex> lock(mu_);
    failed = error_;
  }
  std::vector<int64_t> results;
  uint64_t samples = 0;
  // The runs this batch writes samples to: each must still exist when the
  // batch commits (checked in the same transaction), or the samples would
  // be orphans that the next run given the same id inherits.
  std::vector<int64_t> sample_runs;
  for (const Item& item : batch)
    if (const auto* si = std::get_if<SampleItem>(&item))
      if (sample_runs.empty() || sample_runs.back() != si->run) sample_runs.push_back(si->run);
  using clock = std::chrono::steady_clock;
  std::optional<clock::time_point> stalled_since;  // the first attempt another process's lock refused
  // Runs begun and ended by this batch: the heartbeat's list changes only
  // once the batch has committed.
  std::vector<int64_t> begun, ended;
  const bool heartbeat_due = heartbeat_due_now();
  for (bool retry = true; retry && failed.empty();) {
    retry = false;
    waiting.clear();
    results.clear();
    begun.clear();
    ended.clear();
    samples = 0;
    const auto attempt_started = clock::now();
    try {
      // Once locked out, only the write lock proves the lock gone: a batch
      // of nothing but a heartbeat would otherwise commit as a read.
      db_->exec(locked_out_.load() ? "BEGIN IMMEDIATE" : "BEGIN");
      const std::string now = utc_now();
      for (size_t i = 0; i < batch.size(); ++i) {
        const Item& item = batch[i];
        if (std::holds_alternative<SampleItem>(item)) {
          const size_t end = write_samples(batch, i);
          samples += end - i;
          i = end - 1;  // the for loop's ++i lands on the item after the run
        } else if (auto* ti = std::get_if<TextItem>(&item)) {
          write_text(*ti, now);
        } else if (auto* sy = std::get_if<SyncItem>(&item)) {
          const int64_t result = write_sync(*sy, now, begun, ended);
          waiting.push_back(sy->done);
          results.push_back(result);
        }
      }
      if (heartbeat_due) {
        const double t = unix_now();
        for (int64_t run : open_runs_) heartbeat_.bind(1, t).bind(2, run).exec();
      }
      check_runs_exist(sample_runs);
      db_->exec("COMMIT");
      committed_ += samples;
      if (stalled_since) write_lock_gaps(std::chrono::duration<double>(clock::now() - *stalled_since).count());
      // A run just begun has a fresh mark: its insert wrote it.
      if (heartbeat_due || !begun.empty()) last_heartbeat_ = std::chrono::steady_clock::now();
      for (int64_t run : begun) open_runs_.push_back(run);
      for (int64_t run : ended) open_runs_.erase(std::remove(open_runs_.begin(), open_runs_.end(), run), open_runs_.end());
    } catch (const std::exception& e) {
      sqlite3_exec(db_->handle(), "ROLLBACK", nullptr, nullptr, nullptr);
      const auto* db_error = dynamic_cast<const DbError*>(&e);
      const int code = db_error ? (db_error->sqlite_code & 0xFF) : 0;
      if ((code == SQLITE_BUSY || code == SQLITE_LOCKED) &&
          wait_out_lock(batch, sample_runs, stalled_since, attempt_started)) {
        retry = true;
        continue;
      }
      failed = e.what();
      std::lock_guard<std::mutex> lock(mu_);
      if (error_.empty()) error_ = failed;
      failed = error_;
    }
  }
  if (failed.empty()) {
    for (size_t i = 0; i < waiting.size(); ++i) waiting[i]->set_value(results[i]);
    return;
  }
  fail_batch(batch, failed);
}

// Locked by another process: the whole batch again in a moment, for as
// long as the lock lasts; past busy_limit the samples waiting are given up
// to the lock (their runs then need not exist at commit). True after the
// moment's wait; false to give up (locked out, and stopping or told to).
bool Recorder::wait_out_lock(std::vector<Item>& batch, std::vector<int64_t>& sample_runs,
                             std::optional<std::chrono::steady_clock::time_point>& stalled_since,
                             std::chrono::steady_clock::time_point attempt_started) {
  if (!stalled_since) stalled_since = attempt_started;
  bool stopping = false;
  if (std::chrono::steady_clock::now() - *stalled_since >= options_.busy_limit) {
    std::lock_guard<std::mutex> lock(mu_);
    if (!locked_out_.load()) {
      locked_out_ = true;
      give_up_waiting_samples(batch);
      give_up_waiting_samples(queue_);
      sample_runs.clear();
    }
    stopping = stop_;
  }
  const bool give_up = locked_out_.load() && (stopping || (options_.give_up && options_.give_up()));
  if (give_up) return false;
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  return true;
}

// The run of samples from batch[first] on, full groups through the
// multi-row insert; the index after the run.
size_t Recorder::write_samples(const std::vector<Item>& batch, size_t first) {
  size_t end = first;
  while (end < batch.size() && std::holds_alternative<SampleItem>(batch[end])) ++end;
  size_t i = first;
  for (; end - i >= kSamplesPerInsert; i += kSamplesPerInsert) {
    for (size_t r = 0; r < kSamplesPerInsert; ++r) {
      const auto& si = std::get<SampleItem>(batch[i + r]);
      bind_sample(insert_samples_, int(r) * kSampleColumns, si.run, si.s);
    }
    insert_samples_.step();
    insert_samples_.reset_keep_bindings();
  }
  for (; i < end; ++i) {
    const auto& si = std::get<SampleItem>(batch[i]);
    bind_sample(insert_sample_, 0, si.run, si.s);
    insert_sample_.step();
    insert_sample_.reset_keep_bindings();
  }
  return end;
}

void Recorder::write_text(const TextItem& ti, const std::string& now) {
  switch (ti.kind) {
    case TextItem::Param:
      insert_param_.bind(1, ti.run).bind(2, ti.t).bind(3, int64_t(0)).bind(4, ti.x).bind(5, ti.y).exec();
      break;
    case TextItem::Gap:
      insert_gap_.bind(1, ti.run).bind(2, now).bind(3, ti.a).bind(4, ti.b).bind(5, ti.x);
      // t carries the gap's duration; negative: not known.
      if (ti.t >= 0) insert_gap_.bind(6, ti.t); else insert_gap_.bind_null(6);
      insert_gap_.exec();
      break;
    case TextItem::Event:
      insert_event_.bind(1, now);
      if (ti.run > 0) insert_event_.bind(2, ti.run); else insert_event_.bind_null(2);
      insert_event_.bind(3, ti.x).bind(4, ti.y).exec();
      break;
    case TextItem::Notes: set_notes_.bind(1, ti.x).bind(2, ti.run).exec(); break;
    case TextItem::Health:  // a: step, b: invalid, t: age_ms
      insert_health_.bind(1, ti.run).bind(2, ti.a).bind(3, ti.b).bind(4, int64_t(ti.t)).exec();
      break;
  }
}

// A run begun (its id, added to `begun`) or ended (added to `ended`), or a
// flush; what its waiter is told (the new run's id, else 0).
int64_t Recorder::write_sync(const SyncItem& sy, const std::string& now, std::vector<int64_t>& begun,
                             std::vector<int64_t>& ended) {
  if (sy.begin) {
    const RunInfo& r = *sy.begin;
    insert_run_.bind(1, now).bind(2, r.label).bind(3, r.notes).bind(4, r.platform).bind(5, r.firmware)
        .bind(6, int64_t(r.model_hash)).bind(7, int64_t(r.param_hash)).bind(8, r.loop_rate_hz)
        .bind(9, int64_t(r.n)).bind(10, int64_t(r.m)).bind(11, int64_t(r.decimation)).bind(12, r.reference)
        .bind(13, int64_t(::getpid())).bind(14, host_name()).bind(15, unix_now())
        .bind(16, r.kind).bind(17, int64_t(r.w)).bind(18, r.excitation)
        .exec();
    const int64_t id = db_->last_insert_id();
    begun.push_back(id);
    for (const auto& [name, value] : r.params)
      insert_param_.bind(1, id).bind(2, 0.0).bind(3, int64_t(1)).bind(4, name).bind(5, value).exec();
    return id;
  }
  if (sy.end_run > 0) {
    write_end(sy, now);
    ended.push_back(sy.end_run);
  }
  return 0;
}

void Recorder::check_runs_exist(const std::vector<int64_t>& runs) {
  for (int64_t run : runs) {
    run_exists_.bind(1, run);
    const bool exists = run_exists_.step();
    run_exists_.reset();
    if (!exists)
      throw DbError(fmt::format("run {} was deleted from {} by another process while it was being recorded", run,
                                path_),
                    SQLITE_ABORT);
  }
}

// Nothing of this batch is in the file (its transaction rolled back, or
// an earlier write failed): every sample counts lost to its run, which
// is then closed with those losses if the file still takes that much (a
// full disk has the room the rolled-back batch left).
void Recorder::fail_batch(std::vector<Item>& batch, const std::string& failed) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    for (const Item& item : batch)
      if (const auto* si = std::get_if<SampleItem>(&item)) lose_unwritten(si->run, 1);
  }
  for (Item& item : batch)
    if (auto* sy = std::get_if<SyncItem>(&item)) {
      if (sy->end_run > 0)
        close_after_failure(*sy);
      else
        sy->done->set_exception(std::make_exception_ptr(DbError("recording stopped: " + failed, SQLITE_ERROR)));
    }
}

}  // namespace nlsoft::console
