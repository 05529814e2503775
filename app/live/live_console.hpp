#pragma once
// A connected console: the session and device, the simulator child when
// there is one, the recorder, and the parts that drive the firmware
// through them (parameters, reset forensics, references, model uploads,
// runs). Scripts, the `:` line and the TUI all use the same parts, so they
// behave the same way; this class owns the connection and what the parts
// share, and hands the parts out.
//
// Threads: the link's reader thread calls SampleIntake (samples, STATUS)
// and this class's link events (which re-handshake and check for a reset);
// the TUI's worker or a script's thread drives the parts; the TUI's UI
// thread polls counts and snapshots and respawns the simulator; Notices
// take messages from any of them.
//
// Shutdown (disconnect, also from the destructor): a run still going is
// stopped and kept; then the session is closed, so no callback runs after
// it; then the UDP stream is drained and joined; then the recorder is
// flushed and closed; then the simulator is ended and a --no-record
// database removed. The parts are destroyed with the console, but are not
// used after disconnect(): the recorder they write to is gone.
#include <memory>
#include <optional>
#include <string>

#include "app/link/device.hpp"
#include "app/link/session.hpp"
#include "app/live/active_run.hpp"
#include "app/live/board_rig.hpp"
#include "app/live/firmware_resets.hpp"
#include "app/live/live_options.hpp"
#include "app/live/log_limiter.hpp"
#include "app/live/live_params.hpp"
#include "app/live/live_references.hpp"
#include "app/live/live_runs.hpp"
#include "app/live/model_upload.hpp"
#include "app/live/notices.hpp"
#include "app/live/sample_intake.hpp"
#include "app/live/simulator_child.hpp"
#include "app/live/udp_stream.hpp"
#include "app/record/recorder.hpp"
#include "host/rig/rig.hpp"

namespace nlsoft::console {

class LiveConsole {
 public:
  using Progress = std::function<void(size_t done, size_t total)>;

  explicit LiveConsole(LiveOptions options);
  ~LiveConsole();

  // Starts the simulator if asked, opens the port, handshakes, reads the
  // parameter list and configures telemetry. Throws CliError/LinkError/DbError.
  void connect(const Progress& params_progress = {});
  void disconnect();

  // Valid from the construction on: what the console says, and the
  // simulator it started.
  Notices& notices() { return notices_; }
  SimulatorChild& simulator() { return simulator_; }
  // Valid once connect() has returned, until disconnect().
  Device& device() { return *device_; }
  Session& session() { return *session_; }
  Recorder& recorder() { return *recorder_; }
  SampleIntake& samples() { return parts_->intake; }
  LiveParams& params() { return parts_->params; }
  FirmwareResets& resets() { return parts_->resets; }
  LiveReferences& references() { return parts_->references; }
  ModelUpload& model_upload() { return parts_->model_upload; }
  LiveRuns& runs() { return parts_->runs; }

  const std::string& db_path() const { return db_path_; }
  bool recording() const { return options_.record; }  // false: --no-record, the database goes at exit
  const UdpStream* udp() const { return udp_.get(); }
  // The rig the firmware runs, as its rig file says (BoardRig::rig).
  const host::Rig& rig() const { return rig_->rig(); }
  const host::Rig* known_rig() const { return rig_->known(); }
  // A simulator or a pseudo-terminal (QEMU's UART): no baud rate limits
  // what the link carries, as configure_telemetry() assumes too.
  bool link_unlimited() const;

  // Once simulator().respawn() has returned the new one's `port`: ends a
  // run still in progress, reconnects and handshakes; the parameters are
  // re-read, and the session's edits the new simulator does not have are
  // named as after a firmware reset. Throws CliError, LinkError.
  void reconnect_simulator(const std::string& port);

 private:
  // Made in connect() once the session, device and recorder exist, before
  // the session opens. Each holds references to the connection and to the
  // parts declared before it, so the declaration order is the order they
  // are made in.
  struct Parts {
    explicit Parts(LiveConsole& c)
        : run(*c.recorder_),
          intake(run, c.udp_.get()),
          params(*c.device_, *c.rig_, run),
          resets(*c.device_, params, run, c.notices_),
          references(*c.device_, *c.rig_, run),
          model_upload(*c.device_, run),
          runs({*c.device_, *c.session_, run, intake.live(), references, c.simulator_, c.notices_, c.options_,
                c.db_path_}) {}
    ActiveRun run;
    SampleIntake intake;
    LiveParams params;
    FirmwareResets resets;
    LiveReferences references;
    ModelUpload model_upload;
    LiveRuns runs;
  };

  void on_event(const LinkEvent& e);
  // RIG_INFO against the rig file given: one warning per console.
  void check_rig();
  void configure_telemetry();
  std::string trainable_note(const protocol::Info& info, uint8_t mask, int decimation) const;
  // INFO until it answers: a simulator or a board may still be starting.
  void handshake_patiently();
  // A port that may not exist yet (--wait), opened by its by-id name.
  std::string settle_port(const std::string& port);

  LiveOptions options_;
  Notices notices_;
  LogLimiter log_limiter_;  // the link's reader thread only
  SimulatorChild simulator_{options_};
  std::string db_path_;
  bool temp_db_ = false;
  std::string temp_dir_;  // --no-record: the private folder of the temporary database
  std::unique_ptr<Session> session_;
  std::unique_ptr<Device> device_;
  std::unique_ptr<BoardRig> rig_;
  std::unique_ptr<Recorder> recorder_;
  // Created before the session opens and destroyed after it closes, so the
  // link thread (SampleIntake) never sees it appear or go.
  std::unique_ptr<UdpStream> udp_;
  std::unique_ptr<Parts> parts_;
};

}  // namespace nlsoft::console
