// The console's connection: the simulator it starts, the port it opens
// and settles, the handshake, telemetry's configuration, link events and
// what it tells the user. The other concerns of LiveConsole have files of
// their own: live_samples.cpp, live_resets.cpp, live_params.cpp,
// live_uploads.cpp, live_runs.cpp, simulator_exit.cpp.
#include "app/live/live_console.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "host/files/cli_error.hpp"
#include "host/rig/rig_catalog.hpp"

namespace nlsoft::console {

namespace p = nlsoft::protocol;
namespace tf = protocol::telemetry_field;

namespace {

bool is_pty(const std::string& path) { return path.rfind("/dev/pts/", 0) == 0; }

}  // namespace

LiveConsole::LiveConsole(LiveOptions options) : options_(std::move(options)) {}

LiveConsole::~LiveConsole() { disconnect(); }

void LiveConsole::set_notify(Notify n) {
  std::lock_guard<std::mutex> lock(notify_mu_);
  notify_ = std::move(n);
  if (!notify_) return;
  for (const std::string& s : unheard_) notify_(s);
  unheard_.clear();
}

// What is said before anyone listens (the TUI listens from its start, after
// connect()) waits for the first listener.
void LiveConsole::say(const std::string& s) {
  std::lock_guard<std::mutex> lock(notify_mu_);
  if (notify_) notify_(s);
  else if (unheard_.size() < 32) unheard_.push_back(s);
}

const Rig& LiveConsole::rig() const {
  std::lock_guard<std::mutex> lock(rig_mu_);
  if (rig_) return *rig_;
  if (!options_.rig_file.empty()) {
    rig_ = load_rig_arg(options_.rig_file);
    return *rig_;
  }
  const std::string shipped = rig_name_of_platform(device_->info().platform);
  if (shipped.empty())
    throw CliError("the firmware runs a rig of its own (no shipped rig's number); give its rig file: --rig FILE");
  rig_ = load_rig_arg(shipped);
  return *rig_;
}

void LiveConsole::connect(const Progress& params_progress) {
  // A bad --udp target fails before a simulator starts or a board is touched.
  if (!options_.udp.empty()) udp_ = std::make_unique<UdpStream>(options_.udp, [this](const std::string& s) { say(s); });
  std::string port = options_.port;
  // A rig file that cannot be read stops us before a simulator starts.
  if (!options_.rig_file.empty()) rig_file_ = rig_file_id(options_.rig_file);
  if (options_.sim_in_qemu) {
    sim_ = std::make_unique<SimLauncher>();
    port = sim_->start_qemu(options_.qemu_image, options_.qemu_board);
  } else if (!options_.sim_rig.empty()) {
    sim_ = std::make_unique<SimLauncher>();
    port = sim_->start(options_.sim_rig, options_.sim_args);
  }
  if (port.empty()) throw CliError("no port: give a serial device (e.g. /dev/ttyACM0) or --sim hasel");
  if (!sim_) port = settle_port(port);

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
  ro.give_up = [] { return LiveConsole::interrupted(); };
  recorder_ = std::make_unique<Recorder>(db_path_, ro);

  session_ = std::make_unique<Session>(options_.session);
  session_->on_telemetry([this](const p::Telemetry& t, uint32_t lost) { on_telemetry(t, lost); });
  session_->on_ident_sample([this](const p::IdentSample& t, uint32_t lost) { on_ident_sample(t, lost); });
  session_->on_sensor_health([this](const p::SensorHealth& h) { on_sensor_health(h); });
  session_->on_status([this](const p::Status& s) { on_status(s); });
  session_->on_log([this](const p::Log& l) {
    static const char* level[] = {"debug", "info", "warn", "error"};
    say(fmt::format("firmware {}: {}", l.level < 4 ? level[l.level] : "log", l.text));
  });
  session_->on_event([this](const LinkEvent& e) { on_event(e); });
  session_->open(port, options_.baud);
  device_ = std::make_unique<Device>(*session_);
  handshake_patiently();
  check_rig();
  device_->load_params(params_progress);
  // The tick rate converts compute ticks to microseconds from the first sample on.
  const p::Status st = device_->status();
  tick_rate_hz_ = st.tick_rate_hz;
  note_uptime(st.uptime_ms);
  configure_telemetry();
  recorder_->add_link_event(0, "connected", fmt::format("{} {}", port, device_->info().firmware));
}

void LiveConsole::handshake_patiently() {
  // A board may still be booting (QEMU takes a second or two; many USB
  // boards reset when the port opens): keep asking for a while.
  const auto patience = std::chrono::seconds(sim_ && !options_.sim_in_qemu ? 3 : 10);
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
    say(options_.wait.count() < 0
            ? fmt::format("waiting for {} to appear (Ctrl-C gives up)", port)
            : fmt::format("waiting up to {:g} s for {} to appear (Ctrl-C gives up)", wait_s, port));
    if (!wait_for_port(port, options_.wait, [] { return LiveConsole::interrupted(); }))
      throw CliError(LiveConsole::interrupted()
                         ? fmt::format("interrupted while waiting for {}", port)
                         : fmt::format("{} did not appear within {:g} s", port, wait_s));
  }
  const std::string stable = stable_port_path(port, options_.by_id_dir);
  if (stable != port) say(fmt::format("{} is {}: a reconnect follows the board wherever it re-enumerates", port, stable));
  return stable;
}

bool LiveConsole::link_unlimited() const { return sim_ != nullptr || is_pty(session_->port()); }

void LiveConsole::configure_telemetry() {
  const p::Info info = device_->info();
  uint8_t mask = tf::kAll;
  if (!(info.capabilities & p::capability::kYTrue)) mask = uint8_t(mask & ~tf::kYTrue);
  int dec = options_.decimation;
  if (dec <= 0) {
    dec = 1;
    if (sim_ == nullptr && !is_pty(session_->port())) {
      // 8N1: ten bits a byte; keep a fifth of the line for replies.
      const double frame = double(p::telemetry_payload_size(mask, info.n, info.m) + 9);
      const double per_s = 0.8 * options_.baud / 10.0 / frame;
      dec = std::max(1, int(std::ceil(double(info.loop_rate_hz) / per_s)));
    }
  }
  decimation_ = uint16_t(std::min(dec, 65535));
  telemetry_decimation_ = decimation_.load();
  device_->telemetry_config(mask, decimation_.load());
}

void LiveConsole::disconnect() {
  if (running()) {
    try {
      stop_run("console exited");
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
    say(fmt::format("--udp {}: {} samples sent, {} dropped{}", udp_->target(), udp_->sent(), udp_->dropped(),
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
  sim_.reset();
  if (temp_db_) {
    std::error_code ec;
    std::filesystem::remove_all(temp_dir_, ec);
    temp_db_ = false;
  }
}

void LiveConsole::on_event(const LinkEvent& e) {
  const int64_t run = run_id_.load();
  if (recorder_) recorder_->add_link_event(run, link_event_name(e.kind), e.detail);
  switch (e.kind) {
    case LinkEvent::Kind::Down:
      boot_at_down_ns_ = boot_ns_.load();
      resync_after_gap_ = true;
      say("link down: " + e.detail + (session_->will_reopen() ? " (reconnecting)" : ""));
      break;
    case LinkEvent::Kind::Silent: say("link silent: " + e.detail); break;
    case LinkEvent::Kind::Resumed: say("link: " + e.detail); break;
    case LinkEvent::Kind::Foreign: say(e.detail + " (not used; waiting for the device to come back)"); break;
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
        check_for_reset(before, now, st);
        if (run != 0 && (st.run_id != uint32_t(run) || st.run_state == uint8_t(p::RunState::Idle)))
          say(fmt::format("run {} is no longer running on the firmware (reset?); stop it to close the recording", run));
        if (st.telemetry_mask == 0) say("telemetry is off after the reconnect (board reset?); restart the run");
        if (recorder_) recorder_->add_link_event(run, "handshake", fmt::format("uptime {} ms", st.uptime_ms));
      } catch (const std::exception& ex) {
        say(std::string("re-handshake failed: ") + ex.what());
      }
      break;
    }
  }
}

void LiveConsole::check_rig() {
  if (!rig_file_ || rig_warned_) return;
  const std::optional<p::RigInfo> rig = device_->rig();
  if (!rig) return;  // a 1.1 firmware names no rig
  const std::string w = rig_mismatch(*rig, *rig_file_);
  if (w.empty() || rig_warned_.exchange(true)) return;
  say(w);
  if (recorder_) recorder_->add_link_event(run_id_.load(), "rig", w);
}

}  // namespace nlsoft::console
