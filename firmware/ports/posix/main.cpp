// nlsoft-firmware-sim: the firmware core on this machine, serving the
// protocol on a pseudo-terminal with a simulated plant in the loop.
//
//   nlsoft-firmware-sim --rig hasel                 prints /dev/pts/N, runs at 130 Hz
//   nlsoft-firmware-sim --rig lab/arm.toml          any rig file with a [plant]
//   nlsoft-console /dev/pts/N                       talks to it as to a board
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <time.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include "host/paths/install_paths.hpp"
#include "host/rig/firmware_rig.hpp"
#include "host/rig/rig_catalog.hpp"
#include "host/rig/rig_plant.hpp"
#include "host/rig/rig_option.hpp"
#include "firmware/core/firmware.hpp"
#include "firmware/ports/posix/file_flash.hpp"
#include "firmware/ports/posix/pty.hpp"
#include "firmware/ports/posix/sim_hal.hpp"
#include "protocol/rig_shapes.hpp"
#include "shared/model_file.hpp"
#include "shared/version.hpp"

namespace {

using namespace nlsoft;
using Cap = HostCapacity;
using Fw = fw::Firmware<Cap, 16384, fw::kDefaultFeatures | feature::kSettings>;  // no sensor chips; a settings store (--settings)

volatile sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }

// Port memory: generous on a host; room for the largest model the host
// capacity runs.
alignas(4) uint8_t g_model_staging[model_file_max<Cap>()];
// A settings record (--settings).
constexpr size_t kSettingsMax = fw::settings_payload_max(fw::ParamService<Cap>::count());
uint8_t g_settings[kSettingsMax];
uint8_t g_table_staging[8 + 4 * 3 * 20000];
float g_table_points[3 * 20000];

uint64_t now_us() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return uint64_t(ts.tv_sec) * 1000000u + uint64_t(ts.tv_nsec) / 1000u;
}

// Blocks until the port has bytes (or, with POLLOUT, room) or `timeout_us`
// passes; says whether bytes arrived. ppoll, not poll: a control period at
// 10 kHz is 100 us, below poll's millisecond.
bool wait_fd(int fd, short events, uint64_t timeout_us) {
  pollfd p{fd, events, 0};
  const timespec t{time_t(timeout_us / 1000000u), long(timeout_us % 1000000u) * 1000};
  return ::ppoll(&p, 1, &t, nullptr) > 0 && (p.revents & (POLLIN | POLLERR | POLLHUP));
}

std::string fmt_rig(const protocol::RigInfo& r) {
  return std::string("rig ") + r.rig_name + " (m " + std::to_string(r.m) + ", n " + std::to_string(r.n) + ", w " +
         std::to_string(r.w) + ", nd = dd = " + std::to_string(r.nd) + ")";
}

// Why --shape-list cannot be served (empty when it can): a rig with no
// listed shape would accept no model, and the model in force must be one
// of the list, as an image's built-in model is.
std::string shape_list_refusal(const protocol::RigInfo& r, const std::vector<uint8_t>& model) {
  if (r.shapes_size == 0)
    return fmt_rig(r) + ": the simulator has no kernel of a fixed shape for these dimensions, nothing to list";
  protocol::ModelShape s;
  if (!model.empty() && (!protocol::model_shape(model.data(), model.size(), s) ||
                         protocol::accepts(r, s) != protocol::ShapeVerdict::Accepted))
    return fmt_rig(r) + ": the model's shape is not one of the " + std::to_string(protocol::shape_count(r)) +
           " listed (the simulator would serve a list its own model is not in)";
  return {};
}

// Idle, the loop wakes for the heartbeat (STATUS every second) and catches
// the plant up then; this is how late that may be.
constexpr uint64_t kIdleWakeUs = 100000;

// What the command line asks for.
struct SimOptions {
  std::string rig_arg = "hasel", model_path, settings_path;
  double rate = 0;
  bool fast = false, shape_list = false;
  uint32_t seed = 1, step_load_us = 0, pause_after = 0, pause_ms = 1000;
};

void add_options(CLI::App& app, SimOptions& o) {
  nlsoft::host::add_rig_option(&app, o.rig_arg,
                               "the rig: a shipped rig's name or a rig file (docs/rig-file.md) with a [plant] to simulate")
      ->capture_default_str();
  app.add_option("--rate", o.rate, "control loop rate in Hz (default: the rig's rate_hz, e.g. 130 for hasel)")
      ->check(CLI::Range(1.0, 100000.0));
  app.add_flag("--fast", o.fast, "run steps back to back, as fast as the console reads telemetry (tests, throughput)");
  app.add_option("--model", o.model_path, "model file (default: the rig's [model] file among the shipped models)");
  app.add_option("--seed", o.seed, "plant noise seed")->capture_default_str();
  app.add_option("--step-load-us", o.step_load_us,
                 "spend this many microseconds more in each control step of a run, as a heavier controller or a "
                 "busy machine would: a loop that cannot keep its rate (what the console reports then)")
      ->check(CLI::Range(0u, 1000000u));
  app.add_option("--pause-after", o.pause_after,
                 "after this many frames received, stop for --pause-ms (the port unread, no step, no telemetry), as "
                 "a host that does not schedule the simulator would: how a console or a test rides out a stalled "
                 "firmware, at the same point of its conversation however loaded the machine is");
  app.add_option("--pause-ms", o.pause_ms, "how long --pause-after stops, ms")->capture_default_str()->check(
      CLI::Range(1u, 600000u));
  app.add_flag("--shape-list", o.shape_list,
               "serve RIG_INFO accept 0, as an MCU image does: the shapes the simulator has kernels for at the rig's "
               "dimensions, listed, and any other model refused (at XFER_BEGIN by its size, at its header by its "
               "shape); without it, any shape within the limits (accept 1)");
  app.add_option("--settings", o.settings_path,
                 "the board's settings flash, kept in this file (two 16 KiB sectors, created erased when missing): "
                 "SETTINGS save writes the parameters there and the next start applies them (PROTOCOL.md 9.11); "
                 "without it, or when another simulator holds the file, the simulator keeps no settings and INFO has no "
                 "SETTINGS capability");
}

// The model the simulator boots with: --model, else the rig's shipped model
// where the console finds it (host/paths; `tried` lists where it looked).
// False, said on stderr, when a named file cannot be read.
bool read_model(std::string& path, const host::Rig& rig, std::vector<uint8_t>& model, std::string& tried) {
  if (path.empty() && !rig.model.file.empty()) {
    const nlsoft::host::Lookup found = nlsoft::host::find_model_file(rig.model.file);
    path = found.found;
    tried = found.tried_lines();
  }
  if (path.empty()) return true;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "nlsoft-firmware-sim: error: cannot open model file '%s'\n", path.c_str());
    return false;
  }
  model.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  // A file `train` wrote carries its fit after the model, in sections a
  // firmware never reads: the model is the size its header declares (the
  // boot parse still checks that part's CRC).
  if (model.size() > kModelHeaderSize && std::memcmp(model.data(), "NLSM", 4) == 0) {
    const size_t declared =
        model_file_size(model[model_offset::kLayers], detail::rd32(model.data() + model_offset::kParams));
    if (model.size() > declared) model.resize(declared);
  }
  return true;
}

// --settings: the board's settings flash in a file. False, said on stderr,
// when the file cannot be used; a file another simulator holds leaves this
// one without a settings store, as a board without one.
bool attach_settings_file(Fw& firmware, const std::string& path) {
  static fw::posix::FileFlash flash;
  static fw::SettingsStore settings_store(flash, 0, 1);
  std::string error;
  const fw::posix::FileFlash::Opened opened = flash.open(path, error);
  if (opened == fw::posix::FileFlash::Opened::Failed) {
    std::fprintf(stderr, "nlsoft-firmware-sim: error: --settings: %s\n", error.c_str());
    return false;
  }
  // Two consoles with --sim of one rig: the second simulator runs, as a
  // board without a settings store (no SETTINGS capability).
  if (opened == fw::posix::FileFlash::Opened::Busy)
    std::fprintf(stderr, "nlsoft-firmware-sim: --settings: %s; this simulator keeps no settings\n", error.c_str());
  else
    firmware.attach_settings(settings_store, g_settings, sizeof g_settings);
  return true;
}

// The control loop until SIGINT/SIGTERM. Blocks in ppoll between steps
// rather than trying the port: reads are made only when the port has bytes
// (hal.set_readable), so an idle simulator costs a wake-up per step while a
// run is active and ten a second when none is, not a core. A timer slack of
// 1 us keeps the steps on time.
void serve(Fw& firmware, fw::posix::SimHal& hal, int port, double rate, const SimOptions& o) {
  prctl(PR_SET_TIMERSLACK, 1);
  const uint64_t period = uint64_t(1e6 / rate);
  uint32_t pause_after = o.pause_after;
  uint64_t next = now_us();
  while (!g_stop) {
    if (pause_after > 0 && firmware.frames_in() >= pause_after) {
      pause_after = 0;  // once
      const timespec pause{time_t(o.pause_ms / 1000u), long(o.pause_ms % 1000u) * 1000000};
      nanosleep(&pause, nullptr);
    }
    if (o.fast) {  // steps back to back, the port read between every two
      hal.set_readable(true);
      firmware.poll();
      if (firmware.telemetry_has_room())
        firmware.step();
      else
        wait_fd(port, POLLOUT, 5000);
      continue;
    }
    // A run is paced step by step, a late step counted; outside one the
    // plant still moves (it relaxes towards neutral) and the steps due since
    // the last wake-up are made back to back.
    const bool paced = firmware.state() != protocol::RunState::Idle;
    uint64_t now = now_us();
    if (now >= next) {
      if (paced) {
        // Woken a whole period late (the host did not schedule us): what
        // waits on the port is read first, or the step would find the
        // console's keep-alives unread and trip the link watchdog on the
        // simulator's own absence. A board's UART interrupt takes bytes as
        // they come, whatever its loop is doing.
        if (now > next + period) {
          hal.set_readable(wait_fd(port, POLLIN, 0));
          firmware.poll();
        }
        firmware.step();
        if (o.step_load_us > 0 && firmware.state() == protocol::RunState::Running) {
          const timespec load{time_t(o.step_load_us / 1000000u), long(o.step_load_us % 1000000u) * 1000};
          nanosleep(&load, nullptr);
        }
        next += period;
        if (now > next + period) {  // a whole period late: count it and re-anchor
          firmware.count_overrun();
          next = now + period;
        }
      } else {
        for (int due = 0; next <= now; next += period)
          if (++due <= 100000) firmware.step();  // beyond that (a suspended process): skipped
      }
    }
    firmware.poll();
    now = now_us();
    if (paced && now >= next) {
      // Behind (a loaded machine): catch up, but look at the port between
      // steps all the same, or a request waits until the loop is on time.
      hal.set_readable(wait_fd(port, POLLIN, 0));
      continue;
    }
    const uint64_t wait = paced ? next - now : std::max(next > now ? next - now : 0, kIdleWakeUs);
    hal.set_readable(wait_fd(port, POLLIN, wait));
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "nlsoft-firmware-sim: the nlsoft firmware on this machine. It opens a pseudo-terminal, prints its\n"
      "path on the first line of stdout, and serves the wire protocol there with a simulated plant\n"
      "in the loop (telemetry carries the plant's true output as y_true).\n"
      "Example:  nlsoft-firmware-sim --rig hasel   then   nlsoft-console /dev/pts/N"};
  SimOptions o;
  add_options(app, o);
  CLI11_PARSE(app, argc, argv);

  // The rig and its plant, or a clear refusal before the pty exists.
  static host::Rig rig;
  static RigConfig rig_config{};
  PlantKind plant{};
  GenericPlantSpec generic{};
  try {
    rig = host::load_rig_arg(o.rig_arg);
    plant = host::simulated_plant(rig, "--rig").kind;
    if (plant == PlantKind::Generic) generic = host::generic_plant_spec(rig);
    rig_config = host::firmware_rig(rig);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nlsoft-firmware-sim: error: %s\n", e.what());
    return 2;
  }
  const double rate = o.rate > 0 ? o.rate : double(rig_config.rate_hz);

  std::vector<uint8_t> model;
  std::string model_tried;
  if (!read_model(o.model_path, rig, model, model_tried)) return 2;

  fw::posix::Pty pty;
  if (!fw::posix::open_pty(pty)) {
    std::perror("nlsoft-firmware-sim: cannot open a pseudo-terminal");
    return 2;
  }
  prctl(PR_SET_PDEATHSIG, SIGTERM);  // a console that started us takes us along when it dies
  signal(SIGINT, on_signal);
  signal(SIGTERM, on_signal);
  signal(SIGPIPE, SIG_IGN);

  static fw::posix::SimHal hal(pty.master);
  if (!(plant == PlantKind::Generic ? hal.use_generic(generic, o.seed) : hal.use_plant(plant, o.seed))) {
    std::fprintf(stderr, "nlsoft-firmware-sim: error: %s: the [plant] cannot be simulated\n", rig.file.c_str());
    return 2;
  }
  hal.set_period(float(1.0 / rate));
  const fw::Identity id{&rig_config, "nlsoft-posix", kVersionMajor, kVersionMinor, kVersionPatch, uint32_t(rate + 0.5), true};
  const fw::Buffers bufs{g_model_staging, sizeof g_model_staging, g_table_staging, sizeof g_table_staging,
                         g_table_points, uint32_t(sizeof g_table_points / sizeof(float))};
  static std::unique_ptr<Fw> firmware = std::make_unique<Fw>(hal, id, bufs);
  if (o.shape_list) firmware->serve_shape_list();
  if (!o.settings_path.empty() && !attach_settings_file(*firmware, o.settings_path)) return 2;
  const Status s = firmware->begin(model.empty() ? nullptr : model.data(), model.size());
  if (s != Status::Ok) {
    std::fprintf(stderr, "nlsoft-firmware-sim: error: model '%s' refused: %s\n", o.model_path.c_str(), status_name(s));
    return 2;
  }
  if (o.shape_list) {
    const std::string refusal = shape_list_refusal(firmware->rig_info_now(), model);
    if (!refusal.empty()) {
      std::fprintf(stderr, "nlsoft-firmware-sim: error: --shape-list: %s\n", refusal.c_str());
      return 2;
    }
  }
  std::printf("%s\n", pty.path.c_str());
  std::fflush(stdout);
  if (model.empty())
    std::fprintf(stderr,
                 "nlsoft-firmware-sim: no model for %s: runs are refused until one is uploaded (--model FILE "
                 "or $NLSOFT_MODELS names one); looked for it in:%s\n",
                 rig.name.c_str(), model_tried.c_str());
  serve(*firmware, hal, pty.master, rate, o);
  return 0;
}
