#include "app/replay/simulator_in_process.hpp"

#include <fmt/format.h>

#include <deque>

#include "firmware/core/firmware.hpp"
#include "firmware/ports/posix/sim_plant_hal.hpp"
#include "host/files/cli_error.hpp"
#include "host/rig/firmware_rig.hpp"
#include "host/rig/rig_plant.hpp"
#include "protocol/decoder.hpp"
#include "shared/version.hpp"

namespace nlsoft::console {

using host::CliError;
using host::Rig;
using host::firmware_rig;
using host::generic_plant_spec;
using host::simulated_plant;

namespace {

using Cap = HostCapacity;
// nlsoft-firmware-sim's build (firmware/ports/posix/main.cpp): the host
// capacity, its transmit queue, every service but saved settings (a replay
// keeps none).
using Fw = fw::Firmware<Cap, 16384, fw::kDefaultFeatures>;

// The port: bytes in memory, and a clock that moves only when the caller
// steps, by one control period: the firmware's time is the run's steps.
class MemorySimHal final : public fw::posix::SimPlantHal {
 public:
  std::deque<uint8_t> in;
  std::vector<uint8_t> out;
  size_t serial_read(uint8_t* buf, size_t cap) override {
    size_t n = 0;
    while (n < cap && !in.empty()) buf[n++] = in.front(), in.pop_front();
    return n;
  }
  size_t serial_write(const uint8_t* data, size_t len) override {
    out.insert(out.end(), data, data + len);
    return len;
  }
  uint32_t ticks() override { return uint32_t(now_us_); }
  uint32_t tick_rate_hz() const override { return 1000000u; }
  void advance(uint64_t us) { now_us_ += us; }

  // The plant model instead of the simulated plant (PlantStandIn).
  void use_stand_in(const PlantStandIn& p, const float* neutral, int m) {
    stand_in_ = std::make_unique<model::PlantSimulator>(*p.model);
    start_ = p.start;
    neutral_.assign(neutral, neutral + m);
    stand_in_->rest_at(start_.data(), neutral_.data());
  }
  void actuate(const float* u, int m) override {
    if (!stand_in_) return SimPlantHal::actuate(u, m);
    if (!holding_) stand_in_->step(u);
  }
  void read_sensors(float* l, int w) override {
    if (!stand_in_) return SimPlantHal::read_sensors(l, w);
    const int n = int(start_.size()) - w;
    std::copy(stand_in_->channels() + n, stand_in_->channels() + n + w, l);
  }
  bool read_output(float* y, int n) override {
    if (!stand_in_) return SimPlantHal::read_output(y, n);
    std::copy(stand_in_->channels(), stand_in_->channels() + n, y);
    return true;
  }
  void run_begins() override {
    if (!stand_in_) return SimPlantHal::run_begins();
    stand_in_->rest_at(start_.data(), neutral_.data());
    holding_ = false;
  }

 private:
  uint64_t now_us_ = 0;
  std::unique_ptr<model::PlantSimulator> stand_in_;
  std::vector<float> start_, neutral_;
  bool holding_ = true;  // the stand-in stays at the run's start until the run begins
};

}  // namespace

struct SimulatorInProcess::Impl {
  RigConfig config;
  MemorySimHal hal;
  std::vector<uint8_t> model_staging, table_staging;
  std::vector<float> table_points;
  std::unique_ptr<Fw> fw;
  protocol::Decoder decoder;
  std::vector<SimFrame> frames;  // unsolicited, until taken
  uint64_t period_us = 0;

  void decode_out() {
    size_t used = 0;
    while (used < hal.out.size()) {
      protocol::DecodeResult r;
      used += decoder.feed(hal.out.data() + used, hal.out.size() - used, r);
      if (r.kind != protocol::DecodeResult::Kind::Frame) continue;
      frames.push_back({r.frame.header.type, r.frame.header.seq, r.frame.is_reply(),
                        std::vector<uint8_t>(r.frame.payload, r.frame.payload + r.frame.header.length)});
    }
    hal.out.clear();
  }
};

SimulatorInProcess::SimulatorInProcess(const Rig& rig, const std::vector<uint8_t>& model, uint32_t seed,
                                       const PlantStandIn& stand_in)
    : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  // As nlsoft-firmware-sim: the rig's plant and firmware form, its rate.
  s.config = firmware_rig(rig);
  if (stand_in.model) {
    s.hal.use_stand_in(stand_in, s.config.u_neutral, int(s.config.m));
  } else {
    const PlantKind plant = simulated_plant(rig, "replay").kind;
    const bool selected = plant == PlantKind::Generic ? s.hal.use_generic(generic_plant_spec(rig), seed)
                                                     : s.hal.use_plant(plant, seed);
    if (!selected) throw CliError(fmt::format("{}: the [plant] cannot be simulated", rig.file));
  }
  rate_hz_ = s.config.rate_hz;
  s.hal.set_period(float(1.0 / rate_hz_));
  s.period_us = uint64_t(1e6 / rate_hz_);
  s.model_staging.resize(model_file_max<Cap>());
  s.table_staging.resize(8 + 4 * 3 * 20000);
  s.table_points.resize(3 * 20000);
  const fw::Identity id{&s.config, "nlsoft-posix", kVersionMajor, kVersionMinor, kVersionPatch,
                        uint32_t(rate_hz_ + 0.5), true};
  const fw::Buffers bufs{s.model_staging.data(), s.model_staging.size(), s.table_staging.data(),
                         s.table_staging.size(), s.table_points.data(), uint32_t(s.table_points.size())};
  s.fw = std::make_unique<Fw>(s.hal, id, bufs);
  const Status st = s.fw->begin(model.empty() ? nullptr : model.data(), model.size());
  if (st != Status::Ok) throw CliError(fmt::format("the simulator refused the model: {}", status_name(st)));
}

SimulatorInProcess::~SimulatorInProcess() = default;

SimFrame SimulatorInProcess::exchange(const uint8_t* wire, size_t len, uint8_t seq, const char* what) {
  Impl& s = *impl_;
  s.hal.in.insert(s.hal.in.end(), wire, wire + len);
  s.fw->poll();
  s.decode_out();
  for (auto it = s.frames.begin(); it != s.frames.end(); ++it)
    if (it->reply && it->seq == seq) {
      SimFrame f = std::move(*it);
      s.frames.erase(it);
      return f;
    }
  throw CliError(fmt::format("the simulator in this process did not answer {}", what));
}

void SimulatorInProcess::step() {
  Impl& s = *impl_;
  // As the simulator's fast mode: the port served, then the step.
  s.hal.advance(s.period_us);
  s.fw->poll();
  s.fw->step();
  s.decode_out();
}

std::vector<SimFrame> SimulatorInProcess::take_frames() {
  std::vector<SimFrame> f;
  f.swap(impl_->frames);
  return f;
}

}  // namespace nlsoft::console
