#include "app/live/live_console.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "app/cli_error.hpp"
#include "app/link/model_shape_words.hpp"
#include "app/live/param_defaults.hpp"
#include "app/live/param_text.hpp"
#include "app/live/reference_spec.hpp"
#include "app/live/reference_table.hpp"
#include "app/model/model_section.hpp"
#include "app/rig/rig_catalog.hpp"
#include "app/input_file.hpp"
#include "app/output_file.hpp"
#include "app/printable.hpp"
#include "app/record/run_edit.hpp"
#include "app/record/loop_rate.hpp"
#include "app/record/run_store.hpp"
#include "shared/capacity.hpp"
#include "shared/model_file.hpp"
#include "shared/platform_id.hpp"
#include "shared/reference_presets.hpp"

namespace nlsoft::console {

namespace p = nlsoft::protocol;
namespace tf = protocol::telemetry_field;

namespace {

// "Q[1]" -> ("Q", 1); "Q" -> ("Q", -1).
std::pair<std::string, int> split_element(const std::string& name) {
  const size_t open = name.find('[');
  if (open != std::string::npos && name.back() == ']') {
    const std::string idx = name.substr(open + 1, name.size() - open - 2);
    char* end = nullptr;
    const long i = std::strtol(idx.c_str(), &end, 10);
    if (idx.empty() || *end != '\0' || i < 0) throw CliError(fmt::format("'{}': bad element index", name));
    return {name.substr(0, open), int(i)};
  }
  return {name, -1};
}

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
  const uint8_t pl = device_->info().platform;
  if (pl >= kPlatformCount)
    throw CliError("the firmware runs a rig of its own (no shipped rig's number); give its rig file: --rig FILE");
  rig_ = load_rig_arg(platform_name(PlatformId(pl)));
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

void LiveConsole::on_telemetry(const p::Telemetry& t, uint32_t lost_before) {
  on_sample(sample_from(t, 0, tick_rate_hz_.load()), (t.mask & tf::kStep) != 0, lost_before);
}

void LiveConsole::on_ident_sample(const p::IdentSample& t, uint32_t lost_before) {
  on_sample(sample_from(t, 0), true, lost_before);
}

void LiveConsole::on_sample(Sample s, bool has_step, uint32_t lost_before) {
  const int64_t run = run_id_.load();
  if (run == 0) {
    live_.push(s);
    if (udp_) udp_->push(s, 0);
    return;
  }
  const uint64_t k = run_k_.fetch_add(1);
  s.k = k;
  if (k == 0) first_step_ = s.step;
  if (lost_before > 0) {
    run_lost_ += lost_before;
    recorder_->add_gap(run, k == 0 ? 0 : k - 1, lost_before, "telemetry frames lost on the link");
  } else if (resync_after_gap_.exchange(false) && have_last_step_ && has_step) {
    const uint32_t d = std::max<uint16_t>(decimation_.load(), 1);
    const uint32_t missed = (s.step - last_step_.load()) / d;
    if (missed > 1) {
      run_lost_ += missed - 1;
      recorder_->add_gap(run, k == 0 ? 0 : k - 1, missed - 1, "link down");
    }
  }
  recorder_->add_sample(run, s);
  live_.push(s);
  if (udp_) udp_->push(s, run);
  last_step_ = s.step;
  have_last_step_ = true;
  last_sample_ns_ = std::chrono::steady_clock::now().time_since_epoch().count();
}

// The firmware ends a run on its own only through its link watchdog (or a
// fault): STATUS, sent every second, is where that shows, since telemetry
// just stops.
void LiveConsole::on_status(const p::Status& s) {
  tick_rate_hz_ = s.tick_rate_hz;
  note_uptime(s.uptime_ms);
  const int64_t run = run_id_.load();
  if (run != 0 && s.run_id == uint32_t(run) && s.run_state != uint8_t(p::RunState::Running) &&
      s.run_state != uint8_t(p::RunState::Ident) && !user_hold_.load()) {
    left_run_watchdog_ = s.watchdog;
    left_run_state_ = s.run_state;
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

void LiveConsole::note_uptime(uint32_t uptime_ms) {
  boot_ns_ = std::chrono::steady_clock::now().time_since_epoch().count() - int64_t(uptime_ms) * 1000000;
}

void LiveConsole::check_for_reset(const p::Info& before, const p::Info& now, const p::Status& st) {
  const int64_t was = boot_at_down_ns_.load();
  note_uptime(st.uptime_ms);
  // Half a second absorbs the reply latency in the estimates.
  constexpr int64_t kSlackNs = 500000000;
  std::string why;
  if (was != 0 && boot_ns_.load() - was > kSlackNs)
    why = fmt::format("its uptime says it started again {:.1f} s ago", st.uptime_ms / 1000.0);
  else if (now.param_hash != before.param_hash)
    why = "its parameter list changed";
  if (why.empty()) return;
  const auto all = device_->get_all();
  std::vector<std::string> forgotten;
  {
    std::lock_guard<std::mutex> lock(mu_);
    for (const auto& [info, mine] : edits_) {
      for (const auto& [fi, theirs] : all) {
        if (fi.name != info.name) continue;
        bool same = theirs.size() == mine.size();
        for (size_t i = 0; same && i < mine.size(); ++i) same = float(theirs[i]) == float(mine[i]);
        if (!same)
          forgotten.push_back(fmt::format("{} is {} (this session set {})", info.name, format_param_values(fi, theirs),
                                          format_param_values(info, mine)));
      }
    }
    forgotten_ = forgotten;
  }
  ++firmware_resets_;
  say(fmt::format("the firmware has reset ({}): parameters re-read; {}", why,
                  forgotten.empty() ? "none of this session's edits was lost"
                                    : fmt::format("{} edit{} no longer in force; `params reapply` (A in the parameter "
                                                  "panel) sends them again",
                                                  forgotten.size(), forgotten.size() == 1 ? " is" : "s are")));
  for (const std::string& f : forgotten) say("  " + f);
  if (recorder_) recorder_->add_link_event(run_id_.load(), "reset", why);
}

std::vector<std::string> LiveConsole::forgotten_edits() const {
  std::lock_guard<std::mutex> lock(mu_);
  return forgotten_;
}

std::vector<std::string> LiveConsole::reapply_edits() {
  std::vector<std::pair<ParamInfo, std::vector<double>>> edits;
  {
    std::lock_guard<std::mutex> lock(mu_);
    edits = edits_;
  }
  std::vector<std::string> sent;
  for (const auto& [info, values] : edits) {
    // The catalog may have changed with the firmware: send by today's entry.
    const ParamInfo* now = device_->catalog()->find(info.name);
    if (!now) {
      sent.push_back(fmt::format("{}: no longer a parameter of this firmware; skipped", info.name));
      continue;
    }
    const auto echoed = apply_param(*now, values);
    sent.push_back(fmt::format("{} = {}", now->name, format_param_values(*now, echoed)));
  }
  std::lock_guard<std::mutex> lock(mu_);
  forgotten_.clear();
  return sent;
}

std::pair<ParamInfo, int> LiveConsole::resolve_param(const std::string& name) const {
  const auto cat = device_->catalog();
  auto [base, element] = split_element(name);
  const ParamInfo* info = cat->find(base);
  if (!info && element < 0) {
    // "Q0" = Q[0], as in `sweep Q0 1e5 1e6`.
    size_t d = base.size();
    while (d > 0 && std::isdigit(static_cast<unsigned char>(base[d - 1]))) --d;
    if (d > 0 && d < base.size() && cat->find(base.substr(0, d))) {
      element = std::atoi(base.c_str() + d);
      info = cat->find(base.substr(0, d));
    }
  }
  if (!info) cat->require(base);  // throws with the known names
  if (element >= int(info->size))
    throw CliError(fmt::format("{}[{}]: {} has {} element{} (0..{})", info->name, element, info->name, info->size,
                               info->size == 1 ? "" : "s", info->size - 1));
  return {*info, element};
}

std::vector<double> LiveConsole::set_param(const std::string& name, const std::vector<std::string>& values) {
  const auto [pinfo, element] = resolve_param(name);
  const ParamInfo* info = &pinfo;
  std::vector<double> v;
  if (element >= 0) {
    ParamInfo one = *info;
    one.size = 1;
    const std::vector<double> x = parse_param_values(one, expand_param_tokens(one, values));
    v = device_->get(*info);
    v[size_t(element)] = x[0];
  } else {
    v = parse_param_values(*info, expand_param_tokens(*info, values));
  }
  return apply_param(*info, v);
}

std::vector<double> LiveConsole::apply_param(const ParamInfo& info, const std::vector<double>& values) {
  const std::vector<double> echoed = device_->set(info, values);
  {
    std::lock_guard<std::mutex> lock(mu_);
    edits_.erase(std::remove_if(edits_.begin(), edits_.end(), [&](const auto& e) { return e.first.name == info.name; }),
                 edits_.end());
    edits_.emplace_back(info, echoed);
  }
  if (const int64_t run = run_id_.load()) {
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - run_started()).count();
    recorder_->add_param_change(run, t, info.name, format_param_values(info, echoed));
  }
  return echoed;
}

std::pair<ParamInfo, std::vector<double>> LiveConsole::get_param(const std::string& name) {
  const ParamInfo info = resolve_param(name).first;
  return {info, device_->get(info)};
}

void LiveConsole::save_params(const std::string& path) {
  const auto all = device_->get_all();
  const p::Info info = device_->info();
  OutputFile out(path);
  fmt::print(out.get(), "# nlsoft parameters: {} {}.{}.{}, platform {}, saved {}\n", info.firmware, info.fw_major,
             info.fw_minor, info.fw_patch, int(info.platform), utc_now());
  fmt::print(out.get(), "# NAME VALUES...  (load with `params load FILE`)\n");
  for (const auto& [pi, v] : all) fmt::print(out.get(), "{} {}\n", pi.name, format_param_values(pi, v));
  out.commit();
}

std::vector<std::string> LiveConsole::load_params(const std::string& path, bool dry_run) {
  std::istringstream in(read_input_file(path, kParamsFile));
  const auto cat = device_->catalog();
  std::string line;
  int lineno = 0;
  // Parse and check the whole file before sending anything.
  std::vector<WantedValue> wanted;
  while (std::getline(in, line)) {
    ++lineno;
    std::istringstream ls(line);
    std::string name;
    if (!(ls >> name) || name[0] == '#') continue;
    const ParamInfo* info = cat->find(name);
    if (!info) throw CliError(fmt::format("{}:{}: unknown parameter '{}'; the firmware has: {}", path, lineno,
                                            printable_excerpt(name), cat->names()));
    std::vector<std::string> tokens;
    std::string t;
    while (ls >> t) tokens.push_back(t);
    try {
      wanted.push_back({*info, parse_param_values(*info, expand_param_tokens(*info, tokens)), fmt::format("{}:{}", path, lineno)});
    } catch (const CliError& e) {
      throw CliError(fmt::format("{}:{}: {}", path, lineno, e.what()));
    }
  }
  return apply_values(wanted, dry_run);
}

std::vector<LiveConsole::WantedValue> LiveConsole::defaults_wanted() const {
  const p::Info info = device_->info();
  const Rig& r = rig();
  if (r.m() != info.m || r.n() != info.n)
    throw CliError(fmt::format("rig file {} has m={} n={}; the firmware runs m={} n={}", r.file, r.m(), r.n(), info.m,
                               info.n));
  const auto defaults = firmware_defaults(r);
  std::vector<WantedValue> wanted;
  for (const ParamInfo& pi : device_->catalog()->all()) {
    const auto d = defaults.find(pi.id);
    if (d == defaults.end() || pi.read_only() || d->second.size() != pi.size) continue;
    wanted.push_back({pi, d->second, "default"});
  }
  return wanted;
}

std::vector<std::string> LiveConsole::params_diff() {
  std::vector<std::string> lines;
  for (const WantedValue& w : defaults_wanted()) {
    const std::vector<double> now = device_->get(w.info);
    if (same_values(now, w.values)) continue;
    lines.push_back(fmt::format("{}: {} (default {})", w.info.name, format_param_named(w.info, now),
                                format_param_named(w.info, w.values)));
  }
  return lines;
}

std::vector<std::string> LiveConsole::reset_params() { return apply_values(defaults_wanted(), false); }

bool LiveConsole::same_values(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (float(a[i]) != float(b[i])) return false;
  return true;
}

std::vector<std::string> LiveConsole::apply_values(const std::vector<WantedValue>& wanted, bool dry_run) {
  struct Change {
    const WantedValue* want;
    std::vector<double> from;
  };
  std::vector<Change> changes;
  std::vector<std::string> diff;
  for (const WantedValue& w : wanted) {
    const std::vector<double> from = device_->get(w.info);
    if (same_values(from, w.values)) continue;
    diff.push_back(fmt::format("{}: {} -> {}", w.info.name, format_param_values(w.info, from),
                               format_param_values(w.info, w.values)));
    changes.push_back({&w, from});
  }
  if (dry_run) return diff;
  for (size_t i = 0; i < changes.size(); ++i) {
    try {
      apply_param(changes[i].want->info, changes[i].want->values);
    } catch (const std::exception& e) {
      // All or nothing, like PARAM_SET itself: put back what went through.
      size_t restored = 0;
      for (size_t j = i; j-- > 0;) {
        try {
          apply_param(changes[j].want->info, changes[j].from);
          ++restored;
        } catch (...) {
        }
      }
      throw CliError(fmt::format("{}: {}; {} earlier change{} rolled back, nothing changed", changes[i].want->origin,
                                 e.what(), restored, restored == 1 ? "" : "s"));
    }
  }
  return diff;
}

void LiveConsole::select_reference(const RefParams& ref) {
  device_->select_reference(ref);
  {
    std::lock_guard<std::mutex> lock(mu_);
    reference_ = ref;
    reference_table_file_.clear();
  }
  log_reference_change(reference_json(ref));
}

// A reference sent during a run is part of what the run measured: it goes
// into the run's parameter log with its time, as `reference`.
void LiveConsole::log_reference_change(const std::string& json) {
  if (const int64_t run = run_id_.load()) {
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - run_started()).count();
    recorder_->add_param_change(run, t, "reference", json);
  }
}

void LiveConsole::upload_table(const std::string& csv_path, uint16_t hold, const Progress& progress) {
  if (!device_->has(p::capability::kXferRefTable))
    throw CliError("this firmware does not accept reference tables (no XFER_REF_TABLE capability)");
  const ReferenceTablePoints pts = read_reference_csv(csv_path, n());
  device_->upload(p::XferKind::RefTable, reference_table_object(pts), progress);
  RefParams r{};
  r.kind = RefKind::Table;
  r.hold = hold == 0 ? 1 : hold;
  device_->select_reference(r);
  {
    std::lock_guard<std::mutex> lock(mu_);
    reference_ = r;
    reference_table_file_ = csv_path;
  }
  log_reference_change(reference_json(r, csv_path));
}

LiveConsole::ModelUpload LiveConsole::upload_model(const std::string& path, const Progress& progress) {
  if (!device_->has(p::capability::kXferModel))
    throw CliError("this firmware does not accept models (no XFER_MODEL capability)");
  if (running()) throw CliError("a model cannot change during a run: stop the run first");
  // Bounded before a byte is read: by the firmware's model_max, or what the
  // console's own capacity holds if that is more, so that a model of
  // another shape is refused by its shape (RIG_INFO, below) rather than its
  // size; the firmware's limit is checked after that.
  const uint32_t fw_limit = device_->transfer_limit(p::XferKind::Model);
  const uint64_t host_max = model_file_max<HostCapacity>();
  // The model's limit, and room for the sections after it (never sent).
  InputKind kind{"model file", std::max<uint64_t>(fw_limit, host_max) + pipeline::kSectionsMax, false};
  if (fw_limit >= host_max) kind.limit_words = "this firmware takes models of at most";
  const std::string text = read_input_file(path, kind);
  // A file may carry sections after its model (train's fit) the firmware
  // never gets: only the model is checked and sent.
  const pipeline::ModelFileParts parts =
      pipeline::split_model_file(reinterpret_cast<const uint8_t*>(text.data()), text.size());
  if (parts.bad_trailer)
    throw CliError(fmt::format("{}: not a usable model file: {}", path, parts.fault));
  const std::vector<uint8_t> bytes(text.begin(), text.begin() + std::ptrdiff_t(parts.model_size));
  // RIG_INFO (protocol 1.2): a shape the firmware has no kernel for would be
  // refused at its header chunk or its commit; refused here, nothing is sent.
  if (const auto rig = device_->rig())
    if (const auto refusal = shape_refusal(path, bytes, *rig)) throw CliError(*refusal);
  // Parsed with copies of the weights, so the check does not depend on the
  // vector's alignment; the same checks the firmware makes at commit.
  std::vector<float> weights(model_params_max<HostCapacity>());
  Model<HostCapacity> m;
  uint8_t file_platform = 255;
  const Status st = parse_model(bytes.data(), bytes.size(), m, weights.data(), uint32_t(weights.size()), &file_platform);
  if (st != Status::Ok) throw CliError(fmt::format("{}: not a usable model file: {}", path, status_name(st)));
  const p::Info info = device_->info();
  if (m.m != info.m || m.n != info.n || m.w != info.w)
    throw CliError(fmt::format("{}: the model has m={} n={} w={}, the firmware's plant m={} n={} w={}", path, m.m, m.n,
                               m.w, info.m, info.n, info.w));
  if (file_platform != 255 && file_platform != info.platform)
    throw CliError(fmt::format("{}: a model of the {} platform; the firmware runs {}", path,
                               platform_name(PlatformId(file_platform)), platform_name(PlatformId(info.platform))));
  const uint32_t limit = device_->transfer_limit(p::XferKind::Model);
  if (limit != 0 && bytes.size() > limit)
    throw CliError(fmt::format("{}: {} bytes; this firmware takes models of at most {} bytes", path, bytes.size(), limit));

  ModelUpload r;
  r.previous_hash = info.model_hash;
  r.bytes = bytes.size();
  r.params = m.param_count;
  r.normalisation = m.norm_count();
  device_->upload(p::XferKind::Model, bytes, progress);
  r.hash = device_->handshake().model_hash;
  if (r.hash != m.hash)
    throw CliError(fmt::format("the firmware accepted the model but reports hash {:08x}, the file's is {:08x}", r.hash,
                               m.hash));
  return r;
}

std::optional<RefParams> LiveConsole::reference() const {
  std::lock_guard<std::mutex> lock(mu_);
  return reference_;
}

// What a run follows when this console sent no reference: the firmware's
// own choice, named as such. At boot that is the rig's paper task with its
// preset parameters; another kind was selected by someone else, with
// parameters this console cannot read back.
std::string LiveConsole::firmware_reference_json() {
  const Rig* r = nullptr;
  try {
    r = &rig();
  } catch (const std::exception&) {
    return "";
  }
  const uint8_t id = device_->status().ref_id;
  if (id == uint8_t(r->reference.kind)) {
    std::string j = reference_json(rig_reference(*r, r->reference.kind));
    j.pop_back();
    return j + ",\"source\":\"the firmware's start-up reference (the rig file's [reference])\"}";
  }
  if (id >= kRefKindCount) return "";
  return fmt::format("{{\"kind\":\"{}\",\"source\":\"selected before this console connected; parameters not known\"}}",
                     reference_kind_name(RefKind(id)));
}

int64_t LiveConsole::start_run(const std::string& label) { return begin_run(label, nullptr, ""); }

int64_t LiveConsole::begin_run(const std::string& label, p::IdentStart* ident, const std::string& excitation_json) {
  if (running()) throw CliError(fmt::format("run {} is already active; stop it first", run_id_.load()));
  if (const std::string err = recorder_->error(); !err.empty()) throw CliError("recording has stopped: " + err);
  check_label(label);
  const p::Info info = device_->info();
  RunInfo ri;
  ri.label = label;
  ri.platform = device_->rig_label();
  ri.firmware = fmt::format("{} {}.{}.{}", info.firmware, info.fw_major, info.fw_minor, info.fw_patch);
  ri.model_hash = info.model_hash;
  ri.param_hash = info.param_hash;
  ri.loop_rate_hz = info.loop_rate_hz;
  ri.n = info.n;
  ri.m = info.m;
  decimation_ = ident ? std::max<uint16_t>(ident->decimation, 1) : telemetry_decimation_.load();
  ri.decimation = decimation_.load();
  if (ident) {
    // Open loop: no reference is followed.
    ri.kind = "ident";
    ri.w = info.w;
    ri.excitation = excitation_json;
  } else {
    {
      std::lock_guard<std::mutex> lock(mu_);
      ri.reference = reference_ ? reference_json(*reference_, reference_table_file_) : "";
    }
    if (ri.reference.empty()) ri.reference = firmware_reference_json();
  }
  for (const auto& [pi, v] : device_->get_all()) ri.params.emplace_back(pi.name, format_param_values(pi, v));
  const int64_t id = recorder_->begin_run(ri);
  run_k_ = 0;
  run_lost_ = 0;
  have_last_step_ = false;
  user_hold_ = false;
  left_run_state_ = 0;
  left_run_watchdog_ = 0;
  resync_after_gap_ = false;
  run_label_ = label;
  run_started_ns_ = std::chrono::steady_clock::now().time_since_epoch().count();
  live_.clear();
  run_id_ = id;
  try {
    if (ident) {
      ident->run_id = uint32_t(id);
      device_->ident_start(*ident);
    } else {
      device_->run_start(uint32_t(id));
    }
  } catch (const std::exception& e) {
    run_id_ = 0;
    decimation_ = telemetry_decimation_.load();
    recorder_->end_run(id, std::string("not started: ") + e.what(), 0, 0);
    if (const auto* nack = dynamic_cast<const NackError*>(&e); ident && nack)
      throw CliError(fmt::format("the firmware refused the identification run: {}", e.what()));
    // WRONG_STATE on field 0 (run_id): another run is active; on no field:
    // the firmware has no model to run (firmware.hpp run_start).
    if (const auto* nack = dynamic_cast<const NackError*>(&e); nack && nack->status() == p::StatusCode::WrongState)
      throw CliError(nack->nack.field == p::kNoField
                         ? "the firmware has no model to run: upload one first (model upload FILE.nlsm)"
                         : "the firmware is already running another run; stop it first");
    throw;
  }
  session_->take_longest_write_gap();  // the run's own silences from here
  {
    std::lock_guard<std::mutex> lock(mu_);
    session_runs_.push_back(id);
  }
  return id;
}

RunSummary LiveConsole::stop_run(const std::string& reason) {
  std::lock_guard<std::mutex> stopping(stop_mu_);
  const int64_t id = run_id_.load();
  if (id == 0) throw CliError("no run is active");
  return stop_run_locked(id, reason);
}

RunSummary LiveConsole::finish_run(int64_t id, const std::string& label, const std::string& reason) {
  std::lock_guard<std::mutex> stopping(stop_mu_);
  if (run_id_.load() == id) return stop_run_locked(id, reason);
  // Someone else stopped it; their stop_run finished under stop_mu_.
  std::lock_guard<std::mutex> lock(mu_);
  if (last_run_ && last_run_->run_id == id) return *last_run_;
  RunSummary s;
  s.run_id = id;
  s.label = label;
  s.end_reason = "stopped";
  return s;
}

RunSummary LiveConsole::stop_run_locked(int64_t id, const std::string& reason) {
  std::string why = reason;
  // A simulator that has ended has nothing to stop: asking it would only
  // time out and bury the reason under "link lost at stop".
  if (simulator_exit().empty()) {
    try {
      device_->run_stop();
    } catch (const std::exception& e) {
      // Keeps why the run ended (an early end's cause comes first).
      why = reason + "; link lost at stop: " + e.what();
    }
  }
  // Every frame of the run came before RUN_STOP's ACK on the one reader.
  run_id_ = 0;
  decimation_ = telemetry_decimation_.load();
  recorder_->end_run(id, why, run_k_.load(), run_lost_.load());
  RunSummary s;
  s.run_id = id;
  s.label = run_label_;
  s.end_reason = why;
  s.metrics = metrics_of(id);
  if (const std::string w = loop_rate_warning(s.metrics); !w.empty()) say(fmt::format("run {}: {}", id, w));
  // Samples that arrived and could not be saved (a database locked past
  // --db-busy, a full queue) are in the run's gaps; say so at its end.
  if (const Recorder::Loss loss = recorder_->loss(id); loss.samples > 0)
    say(fmt::format("run {}: {} of {} samples saved; {} lost: {}", id, s.metrics.samples, run_k_.load(), loss.samples,
                    loss.reason));
  std::lock_guard<std::mutex> lock(mu_);
  last_run_ = s;
  return s;
}

void LiveConsole::hold(p::HoldMode mode) {
  if (!running()) throw CliError("no run is active");
  // Set before a hold is sent and cleared only after a resume is
  // acknowledged, so no STATUS of a held run reads as the firmware leaving it.
  if (mode != p::HoldMode::Resume) user_hold_ = true;
  device_->run_hold(mode);
  if (mode == p::HoldMode::Resume) user_hold_ = false;
  recorder_->add_link_event(run_id_.load(), "hold",
                            mode == p::HoldMode::Hold ? "hold" : mode == p::HoldMode::Neutral ? "neutral" : "resume");
}

namespace {

std::string left_run_reason(uint8_t state, uint8_t watchdog, std::chrono::milliseconds console_gap) {
  // STATUS watchdog bit 2: the link went silent during this run.
  constexpr uint8_t kWatchdogTripped = 0x04;
  const char* where = state == uint8_t(p::RunState::Hold)      ? "holding"
                      : state == uint8_t(p::RunState::Neutral) ? "with the actuators neutral"
                      : state == uint8_t(p::RunState::Fault)   ? "in its fault state"
                                                               : "idle";
  // The console's own longest silence beside it: under watchdog_ms, the
  // bytes were written in time and held back on the way (the line, or a
  // host that did not schedule the firmware); the firmware's LOG says how
  // long it heard nothing.
  if (watchdog & kWatchdogTripped)
    return fmt::format("the firmware's link watchdog tripped (nothing from the console for watchdog_ms; the console "
                       "wrote at most {} ms apart during the run); it is {}",
                       console_gap.count(), where);
  return fmt::format("the firmware left the run on its own; it is {}", where);
}

}  // namespace

RunSummary LiveConsole::run_for(double seconds, const std::string& label, const Progress& progress,
                                const std::atomic<bool>* cancel) {
  if (!(seconds > 0)) throw CliError("run duration must be > 0");
  const int64_t id = start_run(label);
  const double rate = loop_rate_hz() > 0 ? loop_rate_hz() : 100.0;
  const uint64_t target = std::max<uint64_t>(1, uint64_t(std::llround(seconds * rate)));
  return run_steps(target, id, label, progress, cancel);
}

RunSummary LiveConsole::run_ident(p::IdentStart start, const std::string& excitation_json, const std::string& label,
                                  const Progress& progress) {
  if (!device_->has(p::capability::kIdent))
    throw CliError(fmt::format("the firmware ({} {}.{}.{}, protocol {}.{}) has no identification runs (the IDENT "
                               "capability of protocol 1.3): update it",
                               device_->info().firmware, device_->info().fw_major, device_->info().fw_minor,
                               device_->info().fw_patch, protocol::kProtocolVersion, device_->protocol_minor()));
  if (start.duration == 0) throw CliError("an identification run must last at least one control step");
  const int64_t id = begin_run(label, &start, excitation_json);
  return run_steps(start.duration, id, label, progress, nullptr);
}

RunSummary LiveConsole::run_steps(uint64_t target, int64_t id, const std::string& label, const Progress& progress,
                                  const std::atomic<bool>* cancel) {
  using clock = std::chrono::steady_clock;
  const double rate = loop_rate_hz() > 0 ? loop_rate_hz() : 100.0;
  const double seconds = double(target) / rate;
  // Telemetry may pause for a link outage the session rides out, or for a
  // slow line's decimation; longer than that, the firmware is not running
  // our run any more.
  const double period_s = double(std::max<uint16_t>(decimation_.load(), 1)) / rate;
  const auto silence = std::max<clock::duration>(
      options_.session.silence_limit, std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(10 * period_s)));
  const auto started = clock::now();
  // A backstop for a step counter that never advances: twice the run, plus
  // the time to start.
  auto deadline = started + std::chrono::milliseconds(int64_t(seconds * 2000.0) + 5000);
  std::string early, record_error;
  bool reached = false;
  bool interrupted = false, stopped = false, cancelled = false, stopped_elsewhere = false;
  bool said_locked_out = false;
  stop_timed_ = false;
  timed_run_ = true;
  while (true) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (cancel && cancel->load()) {
      cancelled = true;
      break;
    }
    if (stop_timed_.exchange(false)) {
      stopped = true;
      break;
    }
    if (LiveConsole::interrupted()) {
      interrupted = true;
      break;
    }
    // No more telemetry will come for a run someone else stopped; polling
    // on would only keep the caller (and a quitting TUI joining its worker)
    // waiting.
    if (run_id_.load() != id) {
      stopped_elsewhere = true;
      break;
    }
    if (const std::string err = recorder_->error(); !err.empty()) {
      record_error = err;
      break;
    }
    if (const std::string gone = simulator_exit(); !gone.empty()) {
      early = gone;
      break;
    }
    if (recorder_->locked_out() && !said_locked_out) {
      said_locked_out = true;
      say(fmt::format("database {} has been locked by another process for over {:g} s (--db-busy): run {}'s samples "
                      "are counted lost until it is released; the run goes on",
                      db_path_, std::chrono::duration<double>(options_.db_busy).count(), id));
    }
    if (const uint8_t st = left_run_state_.load(); st != 0 || left_run_watchdog_.load() != 0) {
      early = left_run_reason(st, left_run_watchdog_.load(), session_->take_longest_write_gap());
      break;
    }
    const auto now = clock::now();
    if (have_last_step_) {
      const uint64_t done = uint64_t(last_step_.load() - first_step_.load()) + decimation_;
      if (progress) progress(std::min(done, target), target);
      if (done >= target) {
        reached = true;
        break;
      }
    }
    if (user_hold_.load()) {  // held on purpose: telemetry pauses, and so does the clock
      deadline += std::chrono::milliseconds(10);
      continue;
    }
    if (now > deadline) {
      early = fmt::format("the firmware's step count did not reach {} steps in {:.0f} s", target,
                          std::chrono::duration<double>(now - started).count());
      break;
    }
    const auto last = have_last_step_ ? clock::time_point(clock::duration(last_sample_ns_.load())) : started;
    if (now - last > silence) {
      early = have_last_step_ ? fmt::format("telemetry stopped arriving (none for {:.1f} s: firmware stopped or link lost)",
                                            std::chrono::duration<double>(now - last).count())
                              : "no telemetry arrived after RUN_START";
      break;
    }
  }
  timed_run_ = false;
  if (!early.empty() && run_id_.load() == id) {
    // The silence the run ended in, as a gap: the frames that fell due in
    // it at the run's rate, at most the steps it still had to go. The steps
    // it never reached after that are no gap (the run ended, as its end
    // says), or a gap would outlast the run itself.
    const uint16_t d = std::max<uint16_t>(decimation_.load(), 1);
    const uint64_t done = have_last_step_ ? uint64_t(last_step_.load() - first_step_.load()) + d : 0;
    const uint64_t missing = done >= target ? 0 : (target - done + d - 1) / d;
    const auto last = have_last_step_ ? clock::time_point(clock::duration(last_sample_ns_.load())) : started;
    const double silent_s = std::chrono::duration<double>(clock::now() - last).count();
    const uint64_t lost = std::min(missing, uint64_t(silent_s * rate / d));
    const uint64_t k = run_k_.load();
    if (missing > 0) {
      run_lost_ += lost;
      recorder_->add_gap(id, k == 0 ? 0 : k - 1, lost, "run ended early: " + early, silent_s);
    }
  }
  if (!record_error.empty()) {
    // The run is stopped on the firmware whatever the database says; closing
    // its row may fail like the rest of the writes did.
    std::string saved;
    try {
      const uint64_t kept = finish_run(id, label, "recording failed: " + record_error).metrics.samples;
      // Counted once the run is stopped: what came until RUN_STOP's ACK too.
      saved = fmt::format("{} of {} samples saved", kept, run_k_.load());
    } catch (const std::exception&) {
      // The same failure again, most likely: not worth repeating.
      saved = fmt::format("{} samples received; the run's row could not be closed either", run_k_.load());
    }
    throw CliError(fmt::format("run {} stopped at once: recording failed ({}); {}", id, record_error, saved));
  }
  RunSummary s = finish_run(id, label,
                            reached       ? "completed"
                            : stopped     ? "stopped by the user"
                            : cancelled   ? "cancelled"
                            : interrupted ? interrupt_reason()
                                          : "ended early: " + early);
  if (stopped_elsewhere || stopped || cancelled) return s;
  if (interrupted)
    throw CliError(fmt::format("{}: run {} stopped and kept ({} samples)", interrupt_reason(), s.run_id,
                               s.metrics.samples));
  if (!early.empty()) {
    s.ended_early = true;
    say(fmt::format("run {} ended early: {}", s.run_id, early));
  }
  return s;
}

std::string LiveConsole::interrupt_reason() {
  switch (interrupted_flag().load()) {
    case SIGINT: return "interrupted by SIGINT (Ctrl-C)";
    case SIGTERM: return "interrupted by SIGTERM";
    case SIGHUP: return "interrupted by SIGHUP (the terminal closed or the connection dropped)";
    case SIGPIPE: return "interrupted by SIGPIPE (standard output's reader is gone)";
    case 0: return "not interrupted";
    default: return fmt::format("interrupted by signal {}", interrupted_flag().load());
  }
}

std::optional<RunSummary> LiveConsole::last_run() const {
  std::lock_guard<std::mutex> lock(mu_);
  return last_run_;
}

std::vector<int64_t> LiveConsole::session_runs() const {
  std::lock_guard<std::mutex> lock(mu_);
  return session_runs_;
}

RunMetrics LiveConsole::metrics_of(int64_t run_id, double skip_s, double window_s) {
  RunStore store(db_path_);
  return run_metrics(store, run_id, skip_s, window_s);
}

}  // namespace nlsoft::console
