#pragma once
// A connected console: the session and device, the simulator child when
// there is one, the recorder, and the run in progress. Scripts, the `:`
// line and the TUI all drive the firmware through this one object, so they
// behave the same way.
#include <atomic>
#include <csignal>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "app/link/device.hpp"
#include "app/link/port_path.hpp"
#include "app/link/rig_hash.hpp"
#include "app/link/session.hpp"
#include "app/link/sim_launcher.hpp"
#include "app/live/live_buffer.hpp"
#include "app/live/udp_stream.hpp"
#include "app/record/recorder.hpp"
#include "app/record/run_metrics.hpp"
#include "host/rig/rig.hpp"
#include "shared/platform_id.hpp"
#include "shared/reference.hpp"

namespace nlsoft::console {

struct LiveOptions {
  std::string port;          // a serial device, or empty with sim_rig/qemu_image
  unsigned baud = 115200;
  std::string qemu_image;    // with sim_in_qemu: the HIL image of the rig (built from its file)
  std::string sim_rig;       // a rig file: start nlsoft-firmware-sim for it
  std::string rig_file;      // the rig the board runs; empty: the shipped rig the firmware names
  bool sim_in_qemu = false;  // ... or boot the Cortex-M4F image in QEMU instead
  std::string qemu_board = "mps2-an386";  // whose image: mps2-an386 or stm32f4
  std::vector<std::string> sim_args;
  std::string db_path;       // empty: default_db_path()
  bool record = true;        // false: a temporary database, deleted on exit
  // --db-busy: how long samples wait in memory for a database another
  // process has locked before they are counted lost (Recorder::Options).
  std::chrono::milliseconds db_busy{30000};
  int decimation = 0;        // 0: 1 on a simulator, else what the baud rate carries
  // --wait: how long to wait for a port that is not there yet (a board
  // being plugged in); 0: fail at once; negative: until Ctrl-C.
  std::chrono::milliseconds wait{0};
  std::string by_id_dir = kSerialByIdDir;  // where udev names USB devices (tests point it elsewhere)
  std::string udp;  // HOST:PORT: stream every telemetry sample there as JSON (PlotJuggler)
  SessionOptions session;
};

struct RunSummary {
  int64_t run_id = 0;
  std::string label, end_reason;
  // A timed run that stopped before its duration for a reason nobody asked
  // for: telemetry stopped (firmware died, link gone), the firmware left the
  // run (its link watchdog tripped). Scripts fail on it unless told not to.
  bool ended_early = false;
  RunMetrics metrics;
};

class LiveConsole {
 public:
  using Notify = std::function<void(const std::string& line)>;
  using Progress = std::function<void(size_t done, size_t total)>;

  explicit LiveConsole(LiveOptions options);
  ~LiveConsole();

  // Messages the user should see (link events, firmware LOG lines, the
  // UDP stream's). May be called from any thread; what was said while none
  // was set (up to 32 messages) goes to the next one set.
  void set_notify(Notify n);

  // Starts the simulator if asked, opens the port, handshakes, reads the
  // parameter list and configures telemetry. Throws CliError/LinkError/DbError.
  void connect(const Progress& params_progress = {});
  void disconnect();

  Device& device() { return *device_; }
  Session& session() { return *session_; }
  Recorder& recorder() { return *recorder_; }
  // The newest samples for the live plots (what a paused plot can scroll
  // back through): 30 s at 500 Hz, ~4 MB.
  static constexpr size_t kLiveSamples = 16384;
  LiveBuffer& live() { return live_; }
  const std::string& db_path() const { return db_path_; }
  const UdpStream* udp() const { return udp_.get(); }
  // The rig the firmware runs, as its rig file says (references, defaults):
  // --sim/--qemu/--rig's file, else the shipped rig the firmware names.
  // Throws CliError when there is none.
  const Rig& rig() const;
  // The rig's name where the platform used to be named (RIG_INFO, protocol
  // 1.2; the platform's name from an older firmware).
  std::string rig_label() const { return device_->rig_label(); }
  double loop_rate_hz() const { return double(device_->info().loop_rate_hz); }
  int n() const { return device_->info().n; }

  // Parameters by name; "Q[1]" addresses one element, the rest keep their
  // value. Returns the echoed value in force. Logs the change into the run.
  std::vector<double> set_param(const std::string& name, const std::vector<std::string>& values);
  std::pair<ParamInfo, std::vector<double>> get_param(const std::string& name);
  // Sends a whole value and logs the change into the active run.
  std::vector<double> apply_param(const ParamInfo& info, const std::vector<double>& values);
  // "Q" -> (Q, -1); "Q[1]" and "Q1" -> (Q, 1). Throws CliError naming the
  // known parameters, or the valid element range.
  std::pair<ParamInfo, int> resolve_param(const std::string& name) const;
  // A firmware that reset while the link was down (its uptime went back, or
  // its parameter list changed) has forgotten this session's edits; the
  // console re-reads the parameters, names the edits no longer in force,
  // and counts the reset (the TUI redraws its panel on the count). This
  // sends the session's edits again, in the order they were made, and
  // returns what it sent.
  std::vector<std::string> reapply_edits();
  std::vector<std::string> forgotten_edits() const;  // "Q is 1e6 (you set 2e6)"
  uint32_t firmware_resets() const { return firmware_resets_.load(); }

  // Returns the lines of the diff; applies nothing if dry_run. On a refusal
  // rolls back what was applied and throws.
  std::vector<std::string> load_params(const std::string& path, bool dry_run = false);
  void save_params(const std::string& path);
  // Against the values the firmware boots with (param_defaults.hpp): every
  // parameter that differs, "Q: 2e+06 2e+06 1e+06 (default 1e+06 2e+06 1e+06)";
  // and all of them put back, all or nothing, returning what changed.
  std::vector<std::string> params_diff();
  std::vector<std::string> reset_params();

  void select_reference(const RefParams& ref);
  void upload_table(const std::string& csv_path, uint16_t hold, const Progress& progress = {});
  std::optional<RefParams> reference() const;

  // A new forward model without a reflash (transfer kind 2). The file is
  // checked here with the firmware's own parser, against the firmware's
  // dimensions, platform, model shape (RIG_INFO) and transfer limit, before a byte is sent; refused
  // during a run (the firmware would refuse the commit). Afterwards INFO is
  // read again and the model hash it reports must be the file's CRC-32.
  struct ModelUpload {
    uint32_t previous_hash = 0, hash = 0;
    size_t bytes = 0;
    uint32_t params = 0, normalisation = 0;  // floats in the file, and how many of them normalise
  };
  ModelUpload upload_model(const std::string& path, const Progress& progress = {});

  // Run control. start_run records the run (when recording) and sends
  // RUN_START; stop_run sends RUN_STOP and closes the run with its metrics.
  int64_t start_run(const std::string& label);
  RunSummary stop_run(const std::string& reason = "stopped");
  void hold(protocol::HoldMode mode);
  bool running() const { return run_id_.load() != 0; }
  int64_t current_run() const { return run_id_.load(); }
  uint64_t run_samples() const { return run_k_.load(); }
  uint64_t run_lost() const { return run_lost_.load(); }
  // Blocks until `seconds` of control steps have been recorded (by the
  // firmware's step count, so a faster-than-real-time simulator finishes
  // early), then stops the run. Ends early, stopping the run, when *cancel
  // becomes true or stop_timed_run() is called; returns at once, with that
  // stop's summary, when another thread stops the run (stop_run, or the
  // console shutting down). Ends early with ended_early set, recording the
  // missing steps as a gap with its duration, when no telemetry comes for
  // the silence limit (or a user hold) or STATUS says the firmware left the
  // run. Throws CliError, after closing the run, if recording fails (disk
  // full): a run nobody can read back is not worth waiting out.
  RunSummary run_for(double seconds, const std::string& label, const Progress& progress = {},
                     const std::atomic<bool>* cancel = nullptr);
  // An identification run (protocol 1.3, IDENT_START): the firmware drives
  // the inputs with its excitation signal for start.duration steps and ends
  // the run itself; recorded as an identification run (kind 'ident', the
  // signal as `excitation` JSON, u, measured y and the sensors per sample).
  // start.run_id is set here. Ends as run_for does (early, interrupted).
  // Throws CliError when the firmware has no IDENT capability or refuses.
  RunSummary run_ident(protocol::IdentStart start, const std::string& excitation_json, const std::string& label,
                       const Progress& progress = {});
  // The decimation telemetry runs at (what a closed-loop run records).
  uint16_t telemetry_decimation() const { return telemetry_decimation_; }
  // A simulator or a pseudo-terminal (QEMU's UART): no baud rate limits
  // what the link carries, as configure_telemetry() assumes too.
  bool link_unlimited() const;

  // --sim/--qemu: how the simulator ended under the console ("simulator
  // killed by signal 9 (SIGKILL)", "simulator exited with status 3"); ""
  // while it runs, or with no simulator. Any thread; a run_for() in
  // progress ends early with these words.
  std::string simulator_exit();
  // Once the simulator has ended: ends the run in progress (not a timed
  // one, which ends itself) with those words as its reason and the time
  // since its last sample as a gap. Returns its summary, if there was one.
  std::optional<RunSummary> end_run_simulator_gone();
  // Starts a new simulator in place of one that has ended; returns its
  // pty. Call it on a thread that lives as long as the console (the TUI's
  // UI thread): the child is ended with the thread that forked it
  // (PR_SET_PDEATHSIG). Throws CliError.
  std::string respawn_simulator();
  // Then: ends a run still in progress, reconnects to `port` and
  // handshakes; the parameters are re-read, and the session's edits the new
  // simulator does not have are named as after a firmware reset. Throws
  // CliError, LinkError.
  void reconnect_simulator(const std::string& port);

  std::optional<RunSummary> last_run() const;
  // Every run this console started, in order (the TUI names them at exit).
  std::vector<int64_t> session_runs() const;
  bool recording() const { return options_.record; }  // false: --no-record, the database goes at exit

  // Ends a run_for() early from another thread (the TUI's stop key while a
  // `run 10s` from the command line is going). Returns false if none is.
  bool stop_timed_run() {
    if (!timed_run_.load()) return false;
    stop_timed_ = true;
    return true;
  }

  // Set from a signal handler (Ctrl-C, SIGTERM, SIGHUP when the terminal
  // closes or the ssh connection drops, SIGPIPE when standard output's
  // reader is gone): run_for() stops the run early and the script runner
  // stops before its next command. Async-signal-safe.
  static void request_interrupt(int signal = SIGINT) { interrupted_flag() = signal; }
  static bool interrupted() { return interrupted_flag() != 0; }
  // "interrupted by SIGHUP (the terminal closed)": what the run's end and
  // the console's last message say.
  static std::string interrupt_reason();
  RunMetrics metrics_of(int64_t run_id, double skip_s = 0, double window_s = 0);

 private:
  struct WantedValue {
    ParamInfo info;  // a copy: the catalog may be reread meanwhile
    std::vector<double> values;
    std::string origin;  // "file:line" or "default", for a refusal's message
  };
  // Sends every value that differs from the one in force, all or nothing
  // (a refusal puts back what went through); returns "name: from -> to".
  std::vector<std::string> apply_values(const std::vector<WantedValue>& wanted, bool dry_run);
  std::vector<WantedValue> defaults_wanted() const;
  static bool same_values(const std::vector<double>& a, const std::vector<double>& b);
  // stop_run's body; the caller holds stop_mu_ and id is the active run.
  RunSummary stop_run_locked(int64_t id, const std::string& reason);
  // Stops run `id` if it is still the active one, else returns the summary
  // of whoever stopped it.
  RunSummary finish_run(int64_t id, const std::string& label, const std::string& reason);
  void on_telemetry(const protocol::Telemetry& t, uint32_t lost_before);
  void on_ident_sample(const protocol::IdentSample& t, uint32_t lost_before);
  void on_sensor_health(const protocol::SensorHealth& h);  // protocol 1.4: recorded beside the samples
  // A run's sample from either message: numbered, gaps recorded, kept.
  void on_sample(Sample s, bool has_step, uint32_t lost_before);
  // start_run's body; an identification run when ident is given.
  int64_t begin_run(const std::string& label, protocol::IdentStart* ident, const std::string& excitation_json);
  // run_for's body over a number of control steps.
  RunSummary run_steps(uint64_t target, int64_t id, const std::string& label, const Progress& progress,
                       const std::atomic<bool>* cancel);
  void on_event(const LinkEvent& e);
  void on_status(const protocol::Status& s);
  // After a reconnect: did the firmware reset, and which edits did it lose?
  void check_for_reset(const protocol::Info& before, const protocol::Info& now, const protocol::Status& st);
  // RIG_INFO against the rig file given (options_.rig_file): one warning per console.
  void check_rig();
  void note_uptime(uint32_t uptime_ms);
  void configure_telemetry();
  // INFO until it answers: a simulator or a board may still be starting.
  void handshake_patiently();
  // A port that may not exist yet (--wait), opened by its by-id name.
  std::string settle_port(const std::string& port);
  void say(const std::string& s);
  void log_reference_change(const std::string& json);
  std::string firmware_reference_json();
  // A lock-free atomic, not a volatile sig_atomic_t: the handler runs on
  // the main thread while the worker's run_for reads it, and a lock-free
  // atomic is both async-signal-safe and free of that data race.
  static std::atomic<int>& interrupted_flag() {
    static_assert(std::atomic<int>::is_always_lock_free, "the signal handler must not take a lock");
    static std::atomic<int> flag{0};
    return flag;
  }

  LiveOptions options_;
  std::optional<RigFileId> rig_file_;
  std::atomic<bool> rig_warned_{false};
  std::string db_path_;
  bool temp_db_ = false;
  std::string temp_dir_;  // --no-record: the private folder of the temporary database
  std::unique_ptr<SimLauncher> sim_;
  // Loaded on first use, then never replaced (references to it stay valid).
  mutable std::mutex rig_mu_;
  mutable std::optional<Rig> rig_;
  std::unique_ptr<Session> session_;
  std::unique_ptr<Device> device_;
  std::unique_ptr<Recorder> recorder_;
  // Created before the session opens and destroyed after it closes, so the
  // link thread (on_telemetry) never sees it appear or go.
  std::unique_ptr<UdpStream> udp_;
  LiveBuffer live_{kLiveSamples};
  Notify notify_;
  std::vector<std::string> unheard_;  // said while notify_ was empty, for the next one set
  std::mutex notify_mu_;

  // Held across a whole stop_run, so two threads stopping the same run (the
  // TUI quitting while a worker's run_for ends it) close it once, and a
  // run_for that saw its run stopped can wait for that stop's summary.
  std::mutex stop_mu_;
  mutable std::mutex mu_;
  std::optional<RefParams> reference_;
  // This session's parameter edits as echoed, oldest first, one per name.
  std::vector<std::pair<ParamInfo, std::vector<double>>> edits_;
  std::vector<std::string> forgotten_;
  std::atomic<uint32_t> firmware_resets_{0};
  // When the firmware booted, on our steady clock, from the last STATUS's
  // uptime; and that estimate when the link went down. A later boot after a
  // reconnect is a reset, whatever the uptimes themselves are.
  std::atomic<int64_t> boot_ns_{0};
  std::atomic<int64_t> boot_at_down_ns_{0};
  std::string reference_table_file_;
  std::optional<RunSummary> last_run_;
  std::vector<int64_t> session_runs_;  // under mu_
  std::atomic<int64_t> run_id_{0};
  std::atomic<uint64_t> run_k_{0};
  std::atomic<uint64_t> run_lost_{0};
  std::atomic<uint32_t> tick_rate_hz_{0};
  std::atomic<bool> resync_after_gap_{false};
  std::atomic<bool> timed_run_{false}, stop_timed_{false};
  std::atomic<bool> have_last_step_{false};
  std::atomic<uint32_t> last_step_{0};
  std::atomic<uint32_t> first_step_{0};
  std::atomic<int64_t> last_sample_ns_{0};  // steady clock, when the run's last sample came
  std::atomic<bool> user_hold_{false};      // hold/neutral asked by us: telemetry pauses on purpose
  std::atomic<uint8_t> left_run_state_{0};  // STATUS: our run's state, when it is no longer Running
  std::atomic<uint8_t> left_run_watchdog_{0};
  std::string run_label_;
  // steady clock ns: the UI thread's parameter edits read it as a run starts.
  std::atomic<int64_t> run_started_ns_{0};
  std::chrono::steady_clock::time_point run_started() const {
    return std::chrono::steady_clock::time_point(std::chrono::steady_clock::duration(run_started_ns_.load()));
  }
  // Both read by the reader thread and run_for while a stop writes them.
  std::atomic<uint16_t> decimation_{1};            // the run's: telemetry's, or an identification run's
  std::atomic<uint16_t> telemetry_decimation_{1};  // TELEMETRY_CONFIG's, put back when an identification run ends
  // How the simulator ended, kept until reconnect_simulator() has ended its
  // run: a new simulator already running must not hide that the old one's
  // run still needs ending.
  std::mutex sim_mu_;
  std::string sim_gone_;
};

}  // namespace nlsoft::console
