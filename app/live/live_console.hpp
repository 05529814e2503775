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
  SampleIntake& samples() { return *intake_; }
  LiveParams& params() { return *params_; }
  FirmwareResets& resets() { return *resets_; }
  LiveReferences& references() { return *references_; }
  ModelUpload& model_upload() { return *model_upload_; }
  LiveRuns& runs() { return *runs_; }

  const std::string& db_path() const { return db_path_; }
  bool recording() const { return options_.record; }  // false: --no-record, the database goes at exit
  const UdpStream* udp() const { return udp_.get(); }
  // The rig the firmware runs, as its rig file says (BoardRig::rig).
  const Rig& rig() const { return rig_->rig(); }
  // A simulator or a pseudo-terminal (QEMU's UART): no baud rate limits
  // what the link carries, as configure_telemetry() assumes too.
  bool link_unlimited() const;

  // Once simulator().respawn() has returned the new one's `port`: ends a
  // run still in progress, reconnects and handshakes; the parameters are
  // re-read, and the session's edits the new simulator does not have are
  // named as after a firmware reset. Throws CliError, LinkError.
  void reconnect_simulator(const std::string& port);

 private:
  void on_event(const LinkEvent& e);
  // RIG_INFO against the rig file given: one warning per console.
  void check_rig();
  void configure_telemetry();
  // INFO until it answers: a simulator or a board may still be starting.
  void handshake_patiently();
  // A port that may not exist yet (--wait), opened by its by-id name.
  std::string settle_port(const std::string& port);

  LiveOptions options_;
  Notices notices_;
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
  // The parts, made in connect() before the session opens; each holds
  // references to the members above and to the parts made before it.
  std::unique_ptr<ActiveRun> run_;
  std::unique_ptr<SampleIntake> intake_;
  std::unique_ptr<LiveParams> params_;
  std::unique_ptr<FirmwareResets> resets_;
  std::unique_ptr<LiveReferences> references_;
  std::unique_ptr<ModelUpload> model_upload_;
  std::unique_ptr<LiveRuns> runs_;
};

}  // namespace nlsoft::console
