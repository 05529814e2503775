// The console's connection: the simulator it starts, the port it opens
// and settles, the handshake, telemetry's configuration, link events, and
// the parts made once it is up.
#include "app/live/live_console.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "app/live/interrupt.hpp"
#include "host/files/cli_error.hpp"

namespace nlsoft::console {

using host::CliError;

namespace p = nlsoft::protocol;
namespace tf = protocol::telemetry_field;

namespace {

bool is_pty(const std::string& path) { return path.rfind("/dev/pts/", 0) == 0; }

}  // namespace

LiveConsole::LiveConsole(LiveOptions options) : options_(std::move(options)) {}

LiveConsole::~LiveConsole() { disconnect(); }

void LiveConsole::connect(const Progress& params_progress) {
  const auto say = [this](const std::string& s) { notices_.say(s); };
  // A bad --udp target fails before a simulator starts or a board is touched.
  if (!options_.udp.empty()) udp_ = std::make_unique<UdpStream>(options_.udp, say);
  session_ = std::make_unique<Session>(options_.session);
  device_ = std::make_unique<Device>(*session_);
  device_->set_give_up([] { return interrupted(); });
  rig_ = std::make_unique<BoardRig>(options_.rig, *device_);
  std::string port = simulator_.start();
  if (!simulator_.present()) port = options_.port;
  if (port.empty()) throw CliError("no port: give a serial device (e.g. /dev/ttyACM0) or --sim hasel");
  if (!simulator_.present()) port = settle_port(port);

  db_path_ = options_.db_path.empty() ? default_db_path() : options_.db_path;
  if (!options_.record) {
    // A folder of our own (0700): the database and its -wal/-shm files are
    // created where nobody else can place a file or a link first.
    char tmpl[] = "/tmp/nlsoft-unrecorded-XXXXXX";
    if (!::mkdtemp(tmpl)) throw CliError(fmt::format("cannot create a temporary database: {}", std::strerror(errno)));
    temp_dir_ = tmpl;
    db_path_ = temp_dir_ + "/runs.db";
    temp_db_ = true;
  }
  // The database first: a locked or damaged file should stop us before we
  // touch the board.
  Recorder::Options ro;
  ro.busy_limit = options_.db_busy;
  ro.give_up = [] { return interrupted(); };
  recorder_ = std::make_unique<Recorder>(db_path_, ro);

  parts_ = std::make_unique<Parts>(*this);

  SampleIntake& intake = parts_->intake;
  session_->on_telemetry([&intake](const p::Telemetry& t, uint32_t lost) { intake.on_telemetry(t, lost); });
  session_->on_ident_sample([&intake](const p::IdentSample& t, uint32_t lost) { intake.on_ident_sample(t, lost); });
  session_->on_sensor_health([&intake](const p::SensorHealth& h) { intake.on_sensor_health(h); });
  session_->on_sensor_sample([&intake](const p::SensorSample& s) { intake.on_sensor_sample(s); });
  session_->on_status([this](const p::Status& s) {
    parts_->intake.on_status(s);
    parts_->resets.note_uptime(s.uptime_ms);
  });
  // The text arrives escaped (Session); a flood is bounded here, before it
  // reaches the terminal and the session log.
  session_->on_log([this](const p::Log& l) {
    static const char* level[] = {"debug", "info", "warn", "error"};
    std::string dropped;
    if (!log_limiter_.admit(std::chrono::steady_clock::now(), dropped)) return;
    if (!dropped.empty()) notices_.say(dropped);
    notices_.say(fmt::format("firmware {}: {}", l.level < 4 ? level[l.level] : "log", l.text));
  });
  session_->on_event([this](const LinkEvent& e) { on_event(e); });
  session_->open(port, options_.baud);
  handshake_patiently();
  check_rig();
  device_->load_params(params_progress);
  // The tick rate converts compute ticks to microseconds from the first sample on.
  const p::Status st = device_->status();
  parts_->intake.on_status(st);
  parts_->resets.note_uptime(st.uptime_ms);
  configure_telemetry();
  recorder_->add_link_event(0, "connected", fmt::format("{} {}", port, device_->info().firmware));
}

void LiveConsole::handshake_patiently() {
  // A board may still be booting (QEMU takes a second or two; many USB
  // boards reset when the port opens): keep asking for a while.
  const auto patience = std::chrono::seconds(simulator_.present() && !options_.sim_in_qemu ? 3 : 10);
  const auto asked = std::chrono::steady_clock::now();
  const LinkStats before = session_->stats();
  while (true) {
    const uint64_t timeouts = session_->stats().timeouts;
    try {
      device_->handshake();
      break;
    } catch (const LinkError&) {
      // An INFO that arrived and was refused (another protocol, impossible
      // dimensions) is its own error; only silence is asked again.
      if (session_->stats().timeouts == timeouts) throw;
      const auto waited = std::chrono::steady_clock::now() - asked;
      if (waited >= patience || session_->foreign_version() != 0)
        throw LinkError(session_->no_info_words(before, waited, options_.baud));
    }
  }
}

std::string LiveConsole::settle_port(const std::string& port) {
  struct stat st {};
  const double wait_s = std::chrono::duration<double>(options_.wait).count();
  if (::stat(port.c_str(), &st) != 0) {
    if (options_.wait.count() == 0)
      throw CliError(fmt::format("{} does not exist: is the board plugged in? --wait SECONDS waits for it", port));
    notices_.say(options_.wait.count() < 0
            ? fmt::format("waiting for {} to appear (Ctrl-C gives up)", port)
            : fmt::format("waiting up to {:g} s for {} to appear (Ctrl-C gives up)", wait_s, port));
    if (!wait_for_port(port, options_.wait, [] { return interrupted(); }))
      throw CliError(interrupted()
                         ? fmt::format("interrupted while waiting for {}", port)
                         : fmt::format("{} did not appear within {:g} s", port, wait_s));
  }
  const std::string stable = stable_port_path(port, options_.by_id_dir);
  if (stable != port)
    notices_.say(fmt::format("{} is {}: a reconnect follows the board wherever it re-enumerates", port, stable));
  return stable;
}

bool LiveConsole::link_unlimited() const { return simulator_.present() || is_pty(session_->port()); }

void LiveConsole::configure_telemetry() {
  const p::Info info = device_->info();
  uint8_t mask = tf::kAll;
  if (!(info.capabilities & p::capability::kYTrue)) mask = uint8_t(mask & ~tf::kYTrue);
  // Closed-loop runs keep the sensors a model reads (PROTOCOL.md 9.6), so
  // `train --run` and `model fit --run` can learn from them.
  const bool sensors = (info.capabilities & p::capability::kSensorStream) != 0 && info.w > 0;
  int dec = options_.decimation;
  if (dec <= 0) {
    dec = 1;
    if (!link_unlimited()) {
      // 8N1: ten bits a byte; keep a fifth of the line for replies. A step
      // with sensors sends its SENSOR_SAMPLE too (4 + 4w payload + 9).
      const double frame = double(p::telemetry_payload_size(mask, info.n, info.m) + 9) +
                           (sensors ? 4.0 * info.w + 13.0 : 0.0);
      const double per_s = 0.8 * options_.baud / 10.0 / frame;
      dec = std::max(1, int(std::ceil(double(info.loop_rate_hz) / per_s)));
    }
  }
  ActiveRun& run = parts_->run;
  run.decimation = uint16_t(std::min(dec, 65535));
  run.telemetry_decimation = run.decimation.load();
  device_->telemetry_config(mask, run.decimation.load());
  if (sensors) device_->sensor_stream(true);
  run.sensors_w = sensors ? info.w : 0;
  if (sensors && dec > 1) notices_.say(trainable_note(info, mask, dec));
}

// Why a closed-loop run of this link cannot be trained from, and the baud
// that would carry every step (PROTOCOL.md 9.6, "With the sensors").
std::string LiveConsole::trainable_note(const p::Info& info, uint8_t mask, int decimation) const {
  const double bytes = double(p::telemetry_payload_size(mask, info.n, info.m) + 9) + 4.0 * info.w + 13.0;
  const double need = double(info.loop_rate_hz) * bytes * 10.0 / 0.8;
  unsigned baud = 0;
  for (const unsigned b : {230400u, 460800u, 921600u, 1000000u, 2000000u})
    if (baud == 0 && b >= need) baud = b;
  return fmt::format(
      "closed-loop runs record every {} step ({:.0f} bytes a step with the sensors at {} Hz over {} baud): "
      "`train --run` and `model fit --run` need every step{}",
      decimation == 2 ? std::string("2nd") : decimation == 3 ? std::string("3rd") : fmt::format("{}th", decimation),
      bytes, info.loop_rate_hz, options_.baud,
      baud ? fmt::format(": --baud {} or more carries them", baud) : std::string(": a native USB port carries them"));
}

void LiveConsole::disconnect() {
  if (parts_ && parts_->runs.running()) {
    try {
      parts_->runs.stop("console exited");
    } catch (...) {
      // Leaving anyway; the run stays open in the database (ended_at NULL).
    }
  }
  // The session first: once it is closed no telemetry callback runs, so the
  // UDP stream's sender thread can be stopped and joined after it.
  if (session_) session_->close();
  if (udp_) {
    // Sends what is queued first: the count said is every datagram sent,
    // what a receiver can check its own count against (UDP promises no
    // delivery).
    udp_->finish();
    notices_.say(fmt::format("--udp {}: {} samples sent, {} dropped{}", udp_->target(), udp_->sent(), udp_->dropped(),
                    udp_->dropped() > 0 ? " (the sender fell behind)" : ""));
    udp_.reset();
  }
  if (recorder_) {
    try {
      recorder_->flush();
    } catch (...) {
    }
  }
  recorder_.reset();
  simulator_.end();
  if (temp_db_) {
    std::error_code ec;
    std::filesystem::remove_all(temp_dir_, ec);
    temp_db_ = false;
  }
}

void LiveConsole::on_event(const LinkEvent& e) {
  const auto say = [this](const std::string& s) { notices_.say(s); };
  const int64_t run = parts_->run.id.load();
  recorder_->add_link_event(run, link_event_name(e.kind), e.detail);
  switch (e.kind) {
    case LinkEvent::Kind::Down:
      parts_->resets.link_down();
      parts_->run.resync_after_gap = true;
      say("link down: " + e.detail + (session_->will_reopen() ? " (reconnecting)" : ""));
      break;
    case LinkEvent::Kind::Silent: say("link silent: " + e.detail); break;
    case LinkEvent::Kind::Resumed: say("link: " + e.detail); break;
    case LinkEvent::Kind::Foreign: say(e.detail + " (not used; waiting for the device to come back)"); break;
    case LinkEvent::Kind::Refused: say("firmware: " + e.detail); break;
    case LinkEvent::Kind::Up: {
      say("link up: " + e.detail + "; re-handshaking (nothing is re-applied)");
      try {
        const p::Info before = device_->info();
        const p::Info now = device_->handshake();
        if (now.param_hash != before.param_hash) {
          device_->load_params();
          say("the firmware's parameter list changed; reloaded it");
        }
        if (now.model_hash != before.model_hash) say(fmt::format("the firmware now runs another model ({:08x})", now.model_hash));
        check_rig();
        const p::Status st = device_->status();
        parts_->resets.check(before, now, st);
        if (run != 0 && (st.run_id != uint32_t(run) || st.run_state == uint8_t(p::RunState::Idle)))
          say(fmt::format("run {} is no longer running on the firmware (reset?); stop it to close the recording", run));
        if (st.telemetry_mask == 0) say("telemetry is off after the reconnect (board reset?); restart the run");
        recorder_->add_link_event(run, "handshake", fmt::format("uptime {} ms", st.uptime_ms));
      } catch (const std::exception& ex) {
        say(std::string("re-handshake failed: ") + ex.what());
      }
      break;
    }
  }
}

void LiveConsole::check_rig() {
  const std::string w = rig_->mismatch();
  if (w.empty()) return;
  notices_.say(w);
  recorder_->add_link_event(parts_->run.id.load(), "rig", w);
}

void LiveConsole::reconnect_simulator(const std::string& port) {
  parts_->runs.end_simulator_gone();
  const p::Info before = device_->info();
  parts_->resets.link_down();
  session_->close();
  try {
    session_->open(port, options_.baud);
    handshake_patiently();
    device_->load_params();
  } catch (...) {
    // Back to "ended", so R can try again with another one.
    simulator_.stop();
    throw;
  }
  const p::Status st = device_->status();
  parts_->intake.on_status(st);
  // A new simulator starts from its defaults: the session's edits it does
  // not have are named, as after a board's reset.
  parts_->resets.check(before, device_->info(), st);
  configure_telemetry();
  simulator_.forget_exit();
  recorder_->add_link_event(0, "restarted", fmt::format("simulator restarted on {} (PID {})", port, simulator_.pid()));
}

}  // namespace nlsoft::console
