// What a board with sensor chips sends when its transmit queue is short
// (PROTOCOL.md 7 DEVICE_STATUS, SENSOR_HEALTH; 9.6): hasel's board image,
// six LIS3MDL on SPI2 and the Cortex-M ports' 512-byte TX queue, over a
// UART that takes a few bytes a millisecond. Every chip that is not ok at
// boot gets its LOG, none dropped, however few bytes the port takes at
// first; a SENSOR_HEALTH never arrives without the sample frame it
// follows; with no chip channel valid its age_ms is 65535, not 0.
#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <set>
#include <string>
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

// The core tests' in-memory port (memory_hal.hpp) as a UART: each
// serial_write takes at most `per_write` bytes (0: the line is busy and
// takes none); the outputs read 0.
class SlowUartHal final : public test::MemoryHal {
 public:
  size_t per_write = 0;
  size_t serial_write(const uint8_t* data, size_t len) override {
    return MemoryHal::serial_write(data, len < per_write ? len : per_write);
  }
  bool read_output(float* y, int n) override {
    for (int j = 0; j < n; ++j) y[j] = 0.0f;
    return true;
  }
};

// The Cortex-M ports' queue (firmware/ports/cortex-m/platform_config.hpp).
constexpr size_t kBoardTxQueue = 512;
using BoardFw = fw::Firmware<HaselCapacity, kBoardTxQueue, fw::kDefaultFeatures | feature::kChips>;

class HaselBoard : public ::testing::Test {
 protected:
  static constexpr int kChips = 6;
  test::FakeChip mags_[kChips] = {test::FakeChip(3), test::FakeChip(3), test::FakeChip(3),
                                  test::FakeChip(3), test::FakeChip(3), test::FakeChip(3)};
  fw::drivers::Chip* chips_[kChips] = {&mags_[0], &mags_[1], &mags_[2], &mags_[3], &mags_[4], &mags_[5]};
  // As rigs/hasel.toml wires them: SPI2 (stm32f4's bus 2), chip selects 0..5.
  const RigDeviceConfig devices_[kChips] = {
      {"mag1", &chips::kLis3mdl, 2, BusKind::Spi, 0, 0, 1000000, {16.0f, 0x60}, {155.0f, 0x02}},
      {"mag2", &chips::kLis3mdl, 2, BusKind::Spi, 0, 1, 1000000, {16.0f, 0x60}, {155.0f, 0x02}},
      {"mag3", &chips::kLis3mdl, 2, BusKind::Spi, 0, 2, 1000000, {16.0f, 0x60}, {155.0f, 0x02}},
      {"mag4", &chips::kLis3mdl, 2, BusKind::Spi, 0, 3, 1000000, {16.0f, 0x60}, {155.0f, 0x02}},
      {"mag5", &chips::kLis3mdl, 2, BusKind::Spi, 0, 4, 1000000, {16.0f, 0x60}, {155.0f, 0x02}},
      {"mag6", &chips::kLis3mdl, 2, BusKind::Spi, 0, 5, 1000000, {16.0f, 0x60}, {155.0f, 0x02}},
  };
  RigSensorSource sources_[18] = {};
  fw::SensorSampler::Slot slots_[kChips];
  std::unique_ptr<fw::SensorSampler> sampler_;
  RigConfig rig_{};
  SlowUartHal hal_;
  alignas(4) uint8_t staging_[model_file_max<HaselCapacity>()];
  uint8_t table_[8 + 4 * 3 * 10];
  float points_[30];
  std::unique_ptr<BoardFw> fw_;
  uint8_t seq_ = 0;

  // Boots the board with every chip answering `answer` at its start.
  void boot(fw::drivers::ChipStatus answer) {
    for (test::FakeChip& m : mags_) m.begin_answer = answer;
    for (int c = 0; c < 18; ++c) sources_[c] = {SensorFrom::Device, uint8_t(c / 3), uint8_t(c % 3), 0.01f, 0.0f};
    sampler_ = std::make_unique<fw::SensorSampler>(chips_, devices_, slots_, kChips, sources_, 18);
    rig_ = test::shipped_config("hasel");
    fw_ = std::make_unique<BoardFw>(hal_, fw::Identity{&rig_, "nlsoft-test", 0, 1, 0, 130, true},
                                    fw::Buffers{staging_, sizeof staging_, table_, sizeof table_, points_, 30});
    fw_->attach_sensors(*sampler_);
    ASSERT_EQ(fw_->begin(nullptr, 0), Status::Ok);
  }

  template <class M>
  void send(const M& m) {
    uint8_t wire[proto::kWireBufferSize];
    const size_t n = proto::encode(m, ++seq_, 0, wire, sizeof wire);
    ASSERT_NE(n, 0u);
    hal_.in.insert(hal_.in.end(), wire, wire + n);
  }

  // Every frame the port has taken so far, decoded, with its payload.
  struct Got {
    uint8_t type;
    bool reply;
    std::vector<uint8_t> payload;
  };
  std::vector<Got> taken() const {
    std::vector<Got> v;
    proto::Decoder dec;
    size_t used = 0;
    while (used < hal_.out.size()) {
      proto::DecodeResult r;
      used += dec.feed(hal_.out.data() + used, hal_.out.size() - used, r);
      if (r.kind == proto::DecodeResult::Kind::Frame)
        v.push_back({r.frame.header.type, r.frame.is_reply(),
                     std::vector<uint8_t>(r.frame.payload, r.frame.payload + r.frame.header.length)});
    }
    return v;
  }
  template <class M>
  std::vector<M> taken_of() const {
    std::vector<M> out;
    for (const Got& g : taken()) {
      if (g.type != uint8_t(M::kType)) continue;
      M x;
      EXPECT_EQ(proto::unpack(g.payload.data(), g.payload.size(), x), proto::StatusCode::Ok);
      out.push_back(x);
    }
    return out;
  }
  // STATUS as the console asks for it, the line free.
  proto::Status status() {
    hal_.per_write = 1u << 20;
    hal_.out.clear();
    send(proto::StatusGet{});
    fw_->poll();
    for (const Got& g : taken())
      if (g.reply && g.type == uint8_t(proto::MsgType::Status)) {
        proto::Status s;
        EXPECT_EQ(proto::unpack(g.payload.data(), g.payload.size(), s), proto::StatusCode::Ok);
        return s;
      }
    ADD_FAILURE() << "no STATUS";
    return {};
  }
};

// The promise of DEVICE_STATUS: at boot, one LOG per chip that is not ok.
// Six of them are more than a 512-byte queue holds beside its reserve
// (three fit): the others wait until the port has taken bytes, and none is
// dropped, nor counted in tx_dropped.
TEST_F(HaselBoard, EveryAbsentChipGetsItsBootLogWhenTheQueueHasRoomNoneDropped) {
  boot(fw::drivers::ChipStatus::kAbsent);
  hal_.per_write = 0;  // the UART busy: nothing leaves during the first polls
  for (int i = 0; i < 5; ++i) fw_->poll();
  hal_.per_write = 12;  // about a millisecond's worth at 115200 baud
  for (int i = 0; i < 200; ++i) fw_->poll();
  std::vector<std::string> logs;
  for (const proto::Log& g : taken_of<proto::Log>()) logs.emplace_back(g.text);
  std::vector<std::string> expected;
  for (int d = 1; d <= kChips; ++d)
    expected.push_back("device mag" + std::to_string(d) +
                       " (lis3mdl): absent; its sensor channels are invalid until it answers again");
  EXPECT_EQ(logs, expected);
  EXPECT_EQ(status().tx_dropped, 0u);
}

// Every chip ok at boot: no LOG at all (only a chip that is not ok is news).
TEST_F(HaselBoard, NoBootLogWhenEveryChipIsOk) {
  boot(fw::drivers::ChipStatus::kOk);
  hal_.per_write = 1u << 20;
  for (int i = 0; i < 20; ++i) fw_->poll();
  EXPECT_TRUE(taken_of<proto::Log>().empty());
}

// A sample frame and its SENSOR_HEALTH are queued together or dropped
// together: every SENSOR_HEALTH that arrives follows the IDENT_SAMPLE of its
// step, and every IDENT_SAMPLE has its SENSOR_HEALTH. With every chip
// absent, each says all 18 channels are invalid and age_ms 65535 (no valid
// chip sample: not 0, a fresh sample's age).
TEST_F(HaselBoard, SensorHealthNeverArrivesWithoutItsSampleAndSaysNoValidSampleAs65535) {
  boot(fw::drivers::ChipStatus::kAbsent);
  hal_.per_write = 1u << 20;
  for (int i = 0; i < 5; ++i) fw_->poll();  // the boot LOGs out
  proto::IdentStart s;
  s.run_id = 7;
  s.signal = uint8_t(proto::IdentSignal::Prbs);
  s.decimation = 1;
  s.seed = 3;
  s.amplitude = 1.0f;
  s.band_lo = 0.2f;
  s.band_hi = 13.0f;
  s.duration = 1000;
  send(s);
  fw_->poll();
  hal_.out.clear();
  hal_.per_write = 40;  // fewer bytes a step than IDENT_SAMPLE and SENSOR_HEALTH take: frames are dropped
  for (int i = 0; i < 60; ++i) fw_->step();
  hal_.per_write = 1u << 20;
  fw_->poll();

  const std::vector<Got> got = taken();
  const uint8_t is = uint8_t(proto::MsgType::IdentSample), sh = uint8_t(proto::MsgType::SensorHealth);
  size_t samples = 0, healths = 0;
  for (size_t k = 0; k < got.size(); ++k) {
    if (got[k].type == is) {
      ++samples;
      EXPECT_TRUE(k + 1 < got.size() && got[k + 1].type == sh) << "an IDENT_SAMPLE without its SENSOR_HEALTH";
    }
    if (got[k].type != sh) continue;
    ++healths;
    proto::SensorHealth h;
    ASSERT_EQ(proto::unpack(got[k].payload.data(), got[k].payload.size(), h), proto::StatusCode::Ok);
    EXPECT_EQ(h.invalid, (1u << 18) - 1u);
    EXPECT_EQ(h.age_ms, 0xFFFFu);
    ASSERT_GT(k, 0u) << "a SENSOR_HEALTH first";
    ASSERT_EQ(got[k - 1].type, is) << "SENSOR_HEALTH of step " << h.step << " without its IDENT_SAMPLE";
    if (k + 1 < got.size()) {
      EXPECT_NE(got[k + 1].type, sh);
    }
    proto::IdentSample sample;
    ASSERT_EQ(proto::unpack(got[k - 1].payload.data(), got[k - 1].payload.size(), sample), proto::StatusCode::Ok);
    EXPECT_EQ(sample.step, h.step);
  }
  // The line took fewer bytes than 60 samples need: some were dropped, and
  // every one that came through came with its health; tx_dropped counts
  // each dropped sample once (its SENSOR_HEALTH went with it).
  EXPECT_LT(samples, 60u);
  EXPECT_GT(samples, 0u);
  EXPECT_EQ(healths, samples);
  EXPECT_EQ(status().tx_dropped, 60u - samples);
}

}  // namespace
