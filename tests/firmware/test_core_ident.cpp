// Identification runs in the firmware core (PROTOCOL.md 9.9), on the host
// with an in-memory port: IDENT_START drives the inputs from the excitation
// signal inside the limits in force, every step's u goes to the actuators,
// IDENT_SAMPLE carries u, the measured y and the sensors; bad parameters are
// refused naming their field; hold, resume, stop and the link watchdog act
// as in a closed-loop run, and the run ends by itself after its duration.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <deque>
#include <memory>
#include <regex>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "fake_chip.hpp"
#include "memory_hal.hpp"
#include "firmware/core/firmware.hpp"
#include "protocol/decoder.hpp"
#include "protocol/encoder.hpp"
#include "shared/capacity.hpp"
#include "shared/chips/lis3mdl.hpp"
#include "support/rig_capacities.hpp"
#include "support/shipped_rigs.hpp"

using namespace nlsoft;
namespace proto = nlsoft::protocol;

namespace {

// The core tests' in-memory port (memory_hal.hpp) whose sensors and
// outputs follow the last u, so a sample shows what was read.
class EchoHal final : public test::MemoryHal {
 public:
  std::vector<std::vector<float>> actuated;
  void actuate(const float* u, int m) override { actuated.emplace_back(u, u + m); }
  void read_sensors(float* l, int w) override {
    for (int i = 0; i < w; ++i) l[i] = 100.0f + float(i) + last_u0();
  }
  bool read_output(float* y, int n) override {
    for (int j = 0; j < n; ++j) y[j] = -float(j) - last_u0();
    return true;
  }

 private:
  float last_u0() const { return actuated.empty() ? 0.0f : actuated.back()[0]; }
};

using Fw = fw::Firmware<HaselCapacity, 1024, fw::kDefaultFeatures | feature::kChips>;  // with a sampler: a test attaches fake chips

class IdentRun : public ::testing::Test {
 protected:
  RigConfig rig_{};
  void SetUp() override {
    rig_ = test::shipped_config("hasel");
    const fw::Identity id{&rig_, "nlsoft-test", 0, 1, 0, 130, true};
    const fw::Buffers b{staging_, sizeof staging_, table_, sizeof table_, points_, 30};
    fw_ = std::make_unique<Fw>(hal_, id, b);
    ASSERT_EQ(fw_->begin(nullptr, 0), Status::Ok);  // no model: an identification run needs none
  }

  template <class M>
  std::pair<uint8_t, std::vector<uint8_t>> request(const M& m) {
    uint8_t wire[proto::kWireBufferSize];
    const size_t n = proto::encode(m, ++seq_, 0, wire, sizeof wire);
    EXPECT_NE(n, 0u);
    hal_.in.insert(hal_.in.end(), wire, wire + n);
    hal_.out.clear();
    fw_->poll();
    for (const proto::FrameView& f : frames())
      if (f.is_reply() && f.header.seq == seq_)
        return {f.header.type, std::vector<uint8_t>(f.payload, f.payload + f.header.length)};
    ADD_FAILURE() << "no reply";
    return {};
  }
  void expect_ack(const proto::IdentStart& s) {
    EXPECT_EQ(request(s).first, uint8_t(proto::MsgType::Ack));
  }
  proto::Nack expect_nack(const proto::IdentStart& s) {
    const auto [type, payload] = request(s);
    proto::Nack n;
    EXPECT_EQ(type, uint8_t(proto::MsgType::Nack));
    if (type == uint8_t(proto::MsgType::Nack)) {
      EXPECT_EQ(proto::unpack(payload.data(), payload.size(), n), proto::StatusCode::Ok);
    }
    return n;
  }

  // Every frame written since the last clear, decoded, payloads copied.
  std::vector<proto::FrameView> frames() {
    std::vector<proto::FrameView> v;
    raw_.clear();
    proto::Decoder dec;
    size_t used = 0;
    while (used < hal_.out.size()) {
      proto::DecodeResult r;
      used += dec.feed(hal_.out.data() + used, hal_.out.size() - used, r);
      if (r.kind == proto::DecodeResult::Kind::Frame) {
        raw_.emplace_back(r.frame.payload, r.frame.payload + r.frame.header.length);
        v.push_back(r.frame);
      }
    }
    // The decoder's views die with it: point them at copies.
    for (size_t i = 0; i < v.size(); ++i) v[i].payload = raw_[i].data();
    return v;
  }
  // The messages of one type among the frames written since the last clear.
  template <class M>
  std::vector<M> written() {
    std::vector<M> out;
    for (const proto::FrameView& f : frames()) {
      if (f.header.type != uint8_t(M::kType)) continue;
      M x;
      EXPECT_EQ(proto::unpack(f, x), proto::StatusCode::Ok);
      out.push_back(x);
    }
    return out;
  }
  std::vector<proto::IdentSample> samples() { return written<proto::IdentSample>(); }
  std::vector<std::string> logs() {
    std::vector<std::string> l;
    for (const proto::Log& g : written<proto::Log>()) l.emplace_back(g.text);
    return l;
  }
  proto::Status status() {
    proto::StatusGet g;
    const auto [type, payload] = request(g);
    proto::Status s;
    EXPECT_EQ(proto::unpack(payload.data(), payload.size(), s), proto::StatusCode::Ok);
    return s;
  }
  void steps(int k) {
    for (int i = 0; i < k; ++i) fw_->step();
  }
  static proto::IdentStart prbs(uint32_t duration) {
    proto::IdentStart s;
    s.run_id = 7;
    s.signal = uint8_t(proto::IdentSignal::Prbs);
    s.decimation = 1;
    s.seed = 3;
    s.amplitude = 1.0f;
    s.band_lo = 0.2f;
    s.band_hi = 13.0f;
    s.duration = duration;
    return s;
  }

  EchoHal hal_;
  alignas(4) uint8_t staging_[model_file_max<HaselCapacity>()];
  uint8_t table_[8 + 4 * 3 * 10];
  float points_[30];
  std::unique_ptr<Fw> fw_;
  uint8_t seq_ = 0;
  std::vector<std::vector<uint8_t>> raw_;
};

TEST_F(IdentRun, DrivesTheInputsInsideTheLimitsAndSendsUMeasuredYAndSensorsEveryStep) {
  expect_ack(prbs(200));
  EXPECT_EQ(status().run_state, uint8_t(proto::RunState::Ident));
  hal_.out.clear();
  hal_.actuated.clear();
  steps(200);
  const std::vector<proto::IdentSample> s = samples();
  ASSERT_EQ(s.size(), 200u);
  ASSERT_EQ(hal_.actuated.size(), 201u);  // the last step's u, then neutral at the end
  bool moved = false;
  for (size_t k = 0; k < s.size(); ++k) {
    EXPECT_EQ(s[k].step, k);
    ASSERT_EQ(s[k].m, 6);
    ASSERT_EQ(s[k].n, 3);
    ASSERT_EQ(s[k].w, 18);
    for (int i = 0; i < 6; ++i) {
      EXPECT_GE(s[k].u[i], rig_.u_min[i]);
      EXPECT_LE(s[k].u[i], rig_.u_max[i]);
      EXPECT_EQ(s[k].u[i], hal_.actuated[k][size_t(i)]) << "the sample's u is the one applied";
    }
    // Sensors and outputs read at the step's start: from the previous u.
    const float prev = k == 0 ? 0.0f : hal_.actuated[k - 1][0];
    EXPECT_EQ(s[k].l[3], 103.0f + prev);
    EXPECT_EQ(s[k].y[1], -1.0f - prev);
    if (k > 0 && s[k].u[0] != s[k - 1].u[0]) moved = true;
    if (k > 0) {
      EXPECT_EQ(uint16_t(s[k].tseq - s[k - 1].tseq), 1u);
    }
  }
  EXPECT_TRUE(moved);
  // Its duration over, the run ends by itself: neutral, idle, said in a LOG.
  for (int i = 0; i < 6; ++i) EXPECT_EQ(hal_.actuated.back()[size_t(i)], rig_.u_neutral[i]);
  // STATUS keeps the ended run's id and its step count: D, not D - 1.
  const proto::Status ended = status();
  EXPECT_EQ(ended.run_state, uint8_t(proto::RunState::Idle));
  EXPECT_EQ(ended.run_id, 7u);
  EXPECT_EQ(ended.step, 200u);
  hal_.out.clear();
  steps(5);
  EXPECT_TRUE(samples().empty());
}

// IDENT_START's signal 4 and options bit 1 reach the generator: an aprbs
// mixed run drives the inputs shared/excitation.hpp computes for that spec,
// bit for bit, with the IDENT_MIXED capability advertised.
TEST_F(IdentRun, AnAprbsMixedRunDrivesTheGeneratorsInputs) {
  proto::IdentStart s = prbs(400);
  s.signal = uint8_t(proto::IdentSignal::Aprbs);
  s.options = proto::ident_options::kMixed;
  expect_ack(s);
  hal_.actuated.clear();
  steps(400);
  ExcitationSpec spec;
  spec.signal = ExcitationSignal::Aprbs;
  spec.mixed = true;
  spec.seed = s.seed, spec.amplitude = s.amplitude, spec.band_lo = s.band_lo, spec.band_hi = s.band_hi;
  spec.duration = s.duration;
  Excitation e;
  ASSERT_EQ(e.configure(spec, 130.0f, rig_.u_min, rig_.u_max, rig_.u_neutral, rig_.m).status, Status::Ok);
  std::set<float> levels;
  for (size_t k = 0; k < 400; ++k) {
    float u[kRigMaxM];
    e.next(u);
    ASSERT_EQ(std::memcmp(u, hal_.actuated[k].data(), 6 * sizeof(float)), 0) << "step " << k;
    levels.insert(u[0]);
  }
  EXPECT_GT(levels.size(), 2u) << "aprbs: more levels than prbs's two";
  proto::InfoGet g;
  const auto [type, payload] = request(g);
  proto::InfoEx ex;
  ASSERT_EQ(proto::unpack(payload.data(), payload.size(), ex), proto::StatusCode::Ok);
  EXPECT_TRUE(ex.info.capabilities & proto::capability::kIdentMixed);
}

TEST_F(IdentRun, TheSameSeedDrivesTheSameInputsAndDecimationThinsTheSamples) {
  proto::IdentStart s = prbs(60);
  expect_ack(s);
  hal_.actuated.clear();
  steps(60);
  const std::vector<std::vector<float>> first(hal_.actuated.begin(), hal_.actuated.begin() + 60);
  s.decimation = 4;
  s.run_id = 8;
  expect_ack(s);
  hal_.actuated.clear();
  hal_.out.clear();
  steps(60);
  const std::vector<std::vector<float>> again(hal_.actuated.begin(), hal_.actuated.begin() + 60);
  EXPECT_EQ(first, again);
  const std::vector<proto::IdentSample> thin = samples();
  ASSERT_EQ(thin.size(), 15u);
  for (size_t k = 0; k < thin.size(); ++k) EXPECT_EQ(thin[k].step, 4 * k);
}

TEST_F(IdentRun, BadParametersAreRefusedNamingTheFieldAndChangeNothing) {
  struct Case {
    void (*edit)(proto::IdentStart&);
    proto::StatusCode status;
    uint8_t field;
  };
  const Case cases[] = {
      // The first value past aprbs: what a firmware without aprbs answers to it.
      {[](proto::IdentStart& s) { s.signal = 5; }, proto::StatusCode::OutOfRange, 1},
      {[](proto::IdentStart& s) { s.signal = 255; }, proto::StatusCode::OutOfRange, 1},
      // Options (field 2) before decimation (field 3).
      {[](proto::IdentStart& s) {
         s.options = proto::ident_options::kJoint | proto::ident_options::kMixed, s.decimation = 0;
       },
       proto::StatusCode::Inconsistent, 2},
      {[](proto::IdentStart& s) { s.options = proto::ident_options::kMixed; },  // prbs: +-1 leaves no spread
       proto::StatusCode::Inconsistent, 2},
      {[](proto::IdentStart& s) { s.decimation = 0; }, proto::StatusCode::OutOfRange, 3},
      {[](proto::IdentStart& s) { s.amplitude = NAN; }, proto::StatusCode::NotFinite, 5},
      {[](proto::IdentStart& s) { s.amplitude = 1.5f; }, proto::StatusCode::OutOfRange, 5},
      {[](proto::IdentStart& s) { s.amplitude = 0.0f; }, proto::StatusCode::OutOfRange, 5},
      {[](proto::IdentStart& s) { s.band_lo = -1.0f; }, proto::StatusCode::OutOfRange, 6},
      {[](proto::IdentStart& s) { s.band_lo = INFINITY; }, proto::StatusCode::NotFinite, 6},
      {[](proto::IdentStart& s) { s.band_hi = 66.0f; }, proto::StatusCode::OutOfRange, 7},  // over 130 Hz / 2
      {[](proto::IdentStart& s) { s.band_lo = 5.0f, s.band_hi = 1.0f; }, proto::StatusCode::Inconsistent, 7},
      {[](proto::IdentStart& s) { s.duration = 0; }, proto::StatusCode::OutOfRange, 8},
  };
  for (const Case& c : cases) {
    proto::IdentStart s = prbs(100);
    c.edit(s);
    const proto::Nack n = expect_nack(s);
    EXPECT_EQ(n.status, uint8_t(c.status)) << "field " << int(c.field);
    EXPECT_EQ(n.field, c.field);
    EXPECT_EQ(status().run_state, uint8_t(proto::RunState::Idle));
  }
  // Another run active: wrong_state on run_id; the same run again: a retry.
  expect_ack(prbs(100));
  proto::IdentStart other = prbs(100);
  other.run_id = 99;
  const proto::Nack busy = expect_nack(other);
  EXPECT_EQ(busy.status, uint8_t(proto::StatusCode::WrongState));
  EXPECT_EQ(busy.field, 0);
  expect_ack(prbs(100));
}

// A retry is known by its run_id alone: other fields in it change nothing,
// the run goes on as it was started (neither restarted nor re-seeded).
TEST_F(IdentRun, ARetryWithOtherFieldsIsAckedAndTheRunGoesOnUnchanged) {
  expect_ack(prbs(1000));
  steps(20);
  proto::IdentStart other = prbs(50);
  other.signal = uint8_t(proto::IdentSignal::Chirp);
  other.seed = 12345;
  other.decimation = 5;
  expect_ack(other);
  hal_.out.clear();
  steps(10);
  const std::vector<proto::IdentSample> s = samples();
  ASSERT_EQ(s.size(), 10u) << "decimation stays 1";
  EXPECT_EQ(s.front().step, 20u) << "not restarted";
  const proto::Status st = status();
  EXPECT_EQ(st.run_state, uint8_t(proto::RunState::Ident));
  EXPECT_EQ(st.step, 30u);
  // The same inputs as a run never retried, step for step.
  proto::RunStop stop;
  EXPECT_EQ(request(stop).first, uint8_t(proto::MsgType::Ack));
  proto::IdentStart fresh = prbs(1000);
  fresh.run_id = 8;
  expect_ack(fresh);
  steps(20);
  hal_.out.clear();
  steps(10);
  const std::vector<proto::IdentSample> again = samples();
  ASSERT_EQ(again.size(), 10u);
  for (size_t k = 0; k < again.size(); ++k)
    for (int i = 0; i < 6; ++i) EXPECT_EQ(again[k].u[i], s[k].u[i]) << "step " << again[k].step;
}

// RUN_START with the identification run's own id is no retry of it: refused
// wrong_state (as IDENT_START with a closed-loop run's id), the run goes on.
TEST_F(IdentRun, RunStartWithTheIdentRunsIdIsWrongState) {
  expect_ack(prbs(1000));
  steps(5);
  proto::RunStart r;
  r.run_id = 7;
  const auto [type, payload] = request(r);
  ASSERT_EQ(type, uint8_t(proto::MsgType::Nack));
  proto::Nack n;
  ASSERT_EQ(proto::unpack(payload.data(), payload.size(), n), proto::StatusCode::Ok);
  EXPECT_EQ(n.request_type, uint8_t(proto::MsgType::RunStart));
  EXPECT_EQ(n.status, uint8_t(proto::StatusCode::WrongState));
  EXPECT_EQ(n.field, 0);
  const proto::Status st = status();
  EXPECT_EQ(st.run_state, uint8_t(proto::RunState::Ident));
  EXPECT_EQ(st.step, 5u);
  hal_.out.clear();
  steps(3);
  EXPECT_EQ(samples().size(), 3u);
}

TEST_F(IdentRun, HoldPausesTheSignalResumeContinuesItAndStopEndsTheRun) {
  expect_ack(prbs(1000));
  steps(10);
  proto::RunHold h;
  h.mode = uint8_t(proto::HoldMode::Hold);
  EXPECT_EQ(request(h).first, uint8_t(proto::MsgType::Ack));
  hal_.actuated.clear();
  hal_.out.clear();
  steps(5);
  EXPECT_TRUE(samples().empty());
  for (const auto& u : hal_.actuated) EXPECT_EQ(u, hal_.actuated.front());
  EXPECT_EQ(status().step, 10u);
  h.mode = uint8_t(proto::HoldMode::Resume);
  EXPECT_EQ(request(h).first, uint8_t(proto::MsgType::Ack));
  EXPECT_EQ(status().run_state, uint8_t(proto::RunState::Ident));
  hal_.out.clear();
  steps(3);
  const std::vector<proto::IdentSample> s = samples();
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].step, 10u);
  EXPECT_EQ(request(proto::RunStop{}).first, uint8_t(proto::MsgType::Ack));
  hal_.actuated.clear();
  hal_.out.clear();
  steps(2);
  EXPECT_TRUE(samples().empty());
  for (int i = 0; i < 6; ++i) EXPECT_EQ(hal_.actuated.back()[size_t(i)], rig_.u_neutral[i]);
}

TEST_F(IdentRun, ASilentLinkTripsTheWatchdogToTheSafeStateAsInClosedLoop) {
  expect_ack(prbs(100000));
  hal_.actuated.clear();
  // No request for well over watchdog_ms (1 s; a millisecond a tick read).
  steps(1500);
  const proto::Status st = status();
  EXPECT_EQ(st.run_state, uint8_t(proto::RunState::Neutral));
  EXPECT_TRUE(st.watchdog & proto::watchdog_flags::kTripped);
  // The first request after the silence is answered with a warning that
  // says how long the silence lasted by the firmware's clock.
  const std::vector<std::string> warned = logs();
  ASSERT_EQ(warned.size(), 1u);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(warned[0], m, std::regex("^link back after ([0-9]+) ms of silence during the run "
                                                         "\\(watchdog_ms 1000\\), actuators went to the safe state")))
      << warned[0];
  EXPECT_GT(std::stoul(m[1]), 1000u);
  EXPECT_LT(std::stoul(m[1]), 3000u);  // 1500 steps, a millisecond a tick read
  status();
  EXPECT_TRUE(logs().empty()) << "said once";
  for (int i = 0; i < 6; ++i) EXPECT_EQ(hal_.actuated.back()[size_t(i)], rig_.u_neutral[i]);
  EXPECT_LT(st.step, 1500u);
  // Nothing resumes by itself; RUN_HOLD resume continues the signal.
  proto::RunHold h;
  h.mode = uint8_t(proto::HoldMode::Resume);
  EXPECT_EQ(request(h).first, uint8_t(proto::MsgType::Ack));
  EXPECT_EQ(status().run_state, uint8_t(proto::RunState::Ident));
}

TEST_F(IdentRun, InputsFollowLimitsNarrowedDuringTheRunAndInfoAdvertisesIt) {
  proto::InfoGet g;
  const auto [type, payload] = request(g);
  proto::InfoEx ex;
  ASSERT_EQ(proto::unpack(payload.data(), payload.size(), ex), proto::StatusCode::Ok);
  EXPECT_TRUE(ex.info.capabilities & proto::capability::kIdent);
  EXPECT_EQ(ex.protocol_minor, 8);  // identification runs (1.3), sensor chips (1.4), settings (1.5), sensor stream (1.6), servos (1.7), samples of one instant (1.8)
  EXPECT_FALSE(ex.info.capabilities & proto::capability::kSettings);  // built without a settings store
  EXPECT_TRUE(ex.info.capabilities & proto::capability::kDevices);
  expect_ack(prbs(400));
  steps(5);
  proto::ParamSet ps;
  ps.id = uint16_t(ParamId::UMax);
  ps.count = 6;
  for (uint8_t i = 0; i < 6; ++i) ps.set_f32(i, 0.25f);
  EXPECT_EQ(request(ps).first, uint8_t(proto::MsgType::ParamValue));
  hal_.out.clear();
  steps(300);
  for (const proto::IdentSample& s : samples())
    for (int i = 0; i < 6; ++i) EXPECT_LE(s.u[i], 0.25f);
}

}  // namespace

namespace {

// A rig whose sensor channels 0 to 2 come from a chip (PROTOCOL.md 9.10):
// its failure is logged once, DEVICE_GET says its state, each sample is
// followed by SENSOR_HEALTH for the same step, and the chip's channels are
// flagged while it is missing, never read as 0 silently; plugged in, it is
// found again within a second.
TEST_F(IdentRun, AChipsStateIsLoggedOnceAskedForAndEachSampleCarriesItsHealth) {
  using Answer = fw::drivers::ChipStatus;
  test::FakeChip mag(3);
  mag.begin_answer = Answer::kAbsent;
  fw::drivers::Chip* chips[] = {&mag};
  const RigDeviceConfig devices[] = {{"tip", &chips::kLis3mdl, 1, BusKind::Spi, 0, 4, 1000000, {16.0f, 0x60}, {1000.0f, 0x02}}};
  RigSensorSource sources[18] = {};
  for (int c = 0; c < 3; ++c) sources[c] = {SensorFrom::Device, 0, uint8_t(c), 2.0f, 1.0f};
  fw::SensorSampler::Slot slots[1];
  fw::SensorSampler sampler(chips, devices, slots, 1, sources, 18);
  fw_ = std::make_unique<Fw>(hal_, fw::Identity{&rig_, "nlsoft-test", 0, 1, 0, 130, true},
                             fw::Buffers{staging_, sizeof staging_, table_, sizeof table_, points_, 30});
  fw_->attach_sensors(sampler);
  ASSERT_EQ(fw_->begin(nullptr, 0), Status::Ok);
  hal_.out.clear();
  fw_->poll();
  fw_->poll();
  EXPECT_EQ(logs(), std::vector<std::string>{"device tip (lis3mdl): absent; its sensor channels are invalid until it "
                                             "answers again"});

  proto::DeviceGet get;
  const auto [type, payload] = request(get);
  ASSERT_EQ(type, uint8_t(proto::MsgType::DeviceStatus));
  proto::DeviceStatus d;
  ASSERT_EQ(proto::unpack(payload.data(), payload.size(), d), proto::StatusCode::Ok);
  EXPECT_EQ(d.count, 1);
  EXPECT_EQ(d.state, uint8_t(proto::DeviceState::Absent));
  EXPECT_EQ(d.bus, 1);
  EXPECT_EQ(d.address, 4);  // SPI: the chip select's number
  EXPECT_EQ(d.age_ms, proto::kNoSample);
  EXPECT_EQ(d.faults, 1u);
  EXPECT_STREQ(d.name, "tip");
  get.index = 1;
  EXPECT_EQ(request(get).first, uint8_t(proto::MsgType::Nack));

  expect_ack(prbs(5000));
  hal_.out.clear();
  steps(2);
  std::vector<uint8_t> order;
  for (const proto::FrameView& f : frames()) order.push_back(f.header.type);
  const uint8_t is = uint8_t(proto::MsgType::IdentSample), sh = uint8_t(proto::MsgType::SensorHealth);
  EXPECT_EQ(order, (std::vector<uint8_t>{is, sh, is, sh}));
  const std::vector<proto::SensorHealth> h = written<proto::SensorHealth>();
  ASSERT_EQ(h.size(), 2u);
  EXPECT_EQ(h[1].step, 1u);
  EXPECT_EQ(h[1].invalid, 0x7u);
  const std::vector<proto::IdentSample> s = samples();
  EXPECT_EQ(s[1].l[0], 1.0f);  // offset + gain * 0: no sample ever, flagged invalid above
  EXPECT_EQ(s[1].l[3], 103.0f + hal_.actuated[0][0]);  // the port's own channel

  // Plugged in: found at the next retry, said once; its samples flow.
  EXPECT_EQ(request(proto::RunStop{}).first, uint8_t(proto::MsgType::Ack));
  mag.begin_answer = Answer::kOk;
  mag.reading[0] = 10.0f, mag.reading[2] = -5.0f;
  hal_.out.clear();
  for (int i = 0; i < 1100; ++i) fw_->poll();  // a millisecond a poll: 1.1 s
  EXPECT_EQ(logs(), std::vector<std::string>{"device tip (lis3mdl): ok"});
  expect_ack(prbs(5000));
  hal_.out.clear();
  steps(1);
  const std::vector<proto::SensorHealth> back = written<proto::SensorHealth>();
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].invalid, 0u);
  EXPECT_LE(back[0].age_ms, 3u);
  EXPECT_EQ(samples()[0].l[0], 21.0f);
  EXPECT_EQ(samples()[0].l[2], -9.0f);
}

}  // namespace
