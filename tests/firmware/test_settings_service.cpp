// SETTINGS (PROTOCOL.md 9.11) through the firmware core, on the host with an
// in-memory port and an in-memory NOR part: what is saved comes back at the
// next boot through PARAM_SET's validation, "defaults" brings the built-in
// values back, a run refuses a save, and the boot says where its settings
// came from once a console speaks.
#include <gtest/gtest.h>

#include <cstring>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "memory_hal.hpp"
#include "firmware/core/firmware.hpp"
#include "firmware/core/settings_service.hpp"
#include "protocol/decoder.hpp"
#include "protocol/encoder.hpp"
#include "shared/capacity.hpp"
#include "support/shipped_rigs.hpp"

using namespace nlsoft;
namespace proto = nlsoft::protocol;

namespace {

using Cap = HostCapacity;
using Fw = fw::Firmware<Cap, 1024, fw::kDefaultFeatures | feature::kSettings>;  // built with settings

using test::MemoryHal;

// Two 4 KiB sectors with a NOR part's rules; `fail` makes every erase fail.
class RamFlash final : public fw::FlashPart {
 public:
  std::vector<uint8_t> mem = std::vector<uint8_t>(2 * 4096, 0xFF);
  bool fail = false;
  uint32_t sector_base(int s) const override { return uint32_t(s) * 4096; }
  uint32_t sector_size(int) const override { return 4096; }
  bool erase(int s) override {
    if (fail) return false;
    std::memset(&mem[sector_base(s)], 0xFF, 4096);
    return true;
  }
  bool program(uint32_t addr, const uint8_t* d, size_t len) override {
    for (size_t i = 0; i < len; ++i) mem[addr + i] &= d[i];
    return true;
  }
  void read(uint32_t addr, uint8_t* out, size_t len) const override { std::memcpy(out, &mem[addr], len); }
};

constexpr size_t kRecordMax = fw::settings_payload_max(fw::ParamService<Cap>::count());

// One board: the firmware over the shared flash; a new Board is a reboot.
class Board {
 public:
  // flash null: a board without a settings store (its SettingsStore sits over a flash never attached).
  Board(RamFlash* flash, const RigConfig& rig) : rig_(rig), store_(flash ? *flash : unattached_, 0, 1) {
    const fw::Identity id{&rig_, "nlsoft-test", 0, 1, 0, 130, false};
    const fw::Buffers b{staging_.data(), staging_.size(), table_, sizeof table_, points_, 30};
    fw_ = std::make_unique<Fw>(hal_, id, b);
    if (flash) fw_->attach_settings(store_, record_, sizeof record_);
  }
  Status begin() { return fw_->begin(nullptr, 0); }

  // One request; its reply's type and payload; the LOG texts that came with it.
  template <class M>
  std::pair<uint8_t, std::vector<uint8_t>> request(const M& m) {
    uint8_t wire[proto::kWireBufferSize];
    const size_t n = proto::encode(m, ++seq_, 0, wire, sizeof wire);
    hal_.in.insert(hal_.in.end(), wire, wire + n);
    hal_.out.clear();
    fw_->poll();
    std::pair<uint8_t, std::vector<uint8_t>> reply{0, {}};
    proto::Decoder dec;
    size_t used = 0;
    while (used < hal_.out.size()) {
      proto::DecodeResult r;
      used += dec.feed(hal_.out.data() + used, hal_.out.size() - used, r);
      if (r.kind != proto::DecodeResult::Kind::Frame) continue;
      if (r.frame.is_reply() && r.frame.header.seq == seq_)
        reply = {r.frame.header.type, std::vector<uint8_t>(r.frame.payload, r.frame.payload + r.frame.header.length)};
      proto::Log g;
      if (r.frame.header.type == uint8_t(proto::MsgType::Log) && proto::unpack(r.frame, g) == proto::StatusCode::Ok)
        logs.push_back(g.text);
    }
    return reply;
  }
  template <class R, class M>
  R expect(const M& m) {
    const auto [type, payload] = request(m);
    R r;
    EXPECT_EQ(type, uint8_t(R::kType)) << proto::message_name(type);
    if (type == uint8_t(R::kType)) {
      EXPECT_EQ(proto::unpack(payload.data(), payload.size(), r), proto::StatusCode::Ok);
    }
    return r;
  }
  proto::Nack settings_nack(proto::SettingsAction a) {
    proto::Settings s;
    s.action = uint8_t(a);
    return expect<proto::Nack>(s);
  }
  void settings_ok(proto::SettingsAction a) {
    proto::Settings s;
    s.action = uint8_t(a);
    const proto::Ack ack = expect<proto::Ack>(s);
    EXPECT_EQ(ack.request_type, uint8_t(proto::MsgType::Settings));
  }
  uint32_t word(uint16_t id, uint8_t i = 0) { return expect<proto::ParamValue>(get(id)).values[i]; }
  float f32(uint16_t id, uint8_t i = 0) { return expect<proto::ParamValue>(get(id)).f32(i); }
  void set_word(uint16_t id, uint32_t v) {
    proto::ParamSet p;
    p.id = id, p.count = 1, p.values[0] = v;
    expect<proto::ParamValue>(p);
  }
  void set_f32(uint16_t id, float v) {
    proto::ParamSet p;
    p.id = id, p.count = 1;
    p.set_f32(0, v);
    expect<proto::ParamValue>(p);
  }
  uint32_t capabilities() { return expect<proto::InfoEx>(proto::InfoGet{}).info.capabilities; }
  std::string last_log() const { return logs.empty() ? "" : logs.back(); }

  std::vector<std::string> logs;

 private:
  static proto::ParamGet get(uint16_t id) {
    proto::ParamGet g;
    g.id = id;
    return g;
  }
  RigConfig rig_;
  RamFlash unattached_;
  fw::SettingsStore store_;
  MemoryHal hal_;
  std::vector<uint8_t> staging_ = std::vector<uint8_t>(64 * 1024);
  uint8_t table_[8 + 4 * 3 * 10];
  float points_[30];
  uint8_t record_[kRecordMax];
  std::unique_ptr<Fw> fw_;
  uint8_t seq_ = 0;
};

constexpr uint16_t kN = uint16_t(ParamId::N), kN1 = uint16_t(ParamId::N1), kNc = uint16_t(ParamId::Nc);
constexpr uint16_t kS = uint16_t(ParamId::S), kWatchdog = uint16_t(fw::FwParamId::WatchdogMs);

class Settings : public ::testing::Test {
 protected:
  void SetUp() override { rig_ = test::shipped_config("hasel"); }
  std::unique_ptr<Board> boot() {
    auto b = std::make_unique<Board>(&flash_, rig_);
    EXPECT_EQ(b->begin(), Status::Ok);
    return b;
  }
  RamFlash flash_;
  RigConfig rig_{};
};

TEST(SettingsWithoutStore, NoCapabilityAndARefusal) {
  const RigConfig rig = test::shipped_config("hasel");
  Board b(nullptr, rig);
  ASSERT_EQ(b.begin(), Status::Ok);
  EXPECT_EQ(b.capabilities() & proto::capability::kSettings, 0u);
  const proto::Nack n = b.settings_nack(proto::SettingsAction::Save);
  EXPECT_EQ(n.status, uint8_t(proto::StatusCode::Unsupported));
  for (const std::string& l : b.logs) EXPECT_EQ(l.find("settings"), std::string::npos) << l;
}

TEST_F(Settings, TheBootSaysWhereItsSettingsCameFromOnceAConsoleSpeaks) {
  auto b = boot();
  EXPECT_NE(b->capabilities() & proto::capability::kSettings, 0u);
  ASSERT_FALSE(b->logs.empty()) << "no LOG after the first request";
  EXPECT_EQ(b->logs.front(), "settings: built-in (nothing saved)");
  b->logs.clear();
  b->capabilities();
  EXPECT_TRUE(b->logs.empty()) << "said once: " << b->last_log();
  b->settings_ok(proto::SettingsAction::Report);
  EXPECT_EQ(b->last_log(), "settings: built-in (nothing saved)");
}

TEST_F(Settings, ASavedSetIsInForceAfterAReboot) {
  const uint32_t builtin_n = rig_.N;
  {
    auto b = boot();
    b->set_word(kN, builtin_n + 3);
    b->set_word(kNc, 2);
    b->set_f32(kS, 0.25f);
    b->set_word(kWatchdog, 2500);
    b->settings_ok(proto::SettingsAction::Save);
    EXPECT_EQ(b->last_log(), "settings: saved to flash, save 1 (" + std::to_string(fw::ParamService<Cap>::count()) +
                                 " values)");
    b->set_word(kN, builtin_n + 1);  // changed after the save: not kept
  }
  auto b = boot();
  EXPECT_EQ(b->word(kN), builtin_n + 3);
  EXPECT_EQ(b->word(kNc), 2u);
  EXPECT_EQ(b->f32(kS), 0.25f);
  EXPECT_EQ(b->word(kWatchdog), 2500u);
  ASSERT_FALSE(b->logs.empty());
  EXPECT_EQ(b->logs.front(),
            "settings: from flash, save 1 (" + std::to_string(fw::ParamService<Cap>::count()) + " values)");
}

TEST_F(Settings, DefaultsPutTheBuiltInValuesBackNowAndAtEveryBoot) {
  {
    auto b = boot();
    b->set_word(kN, rig_.N + 2);
    b->set_word(kWatchdog, 0);
    b->settings_ok(proto::SettingsAction::Save);
    b->settings_ok(proto::SettingsAction::Defaults);
    EXPECT_EQ(b->word(kN), uint32_t(rig_.N));
    EXPECT_EQ(b->word(kWatchdog), uint32_t(FwSettings{}.watchdog_ms));
    EXPECT_EQ(b->last_log(), "settings: built-in (restored by request)");
  }
  auto b = boot();
  EXPECT_EQ(b->word(kN), uint32_t(rig_.N));
  EXPECT_EQ(b->word(kWatchdog), uint32_t(FwSettings{}.watchdog_ms));
  ASSERT_FALSE(b->logs.empty());
  EXPECT_EQ(b->logs.front(), "settings: built-in (restored by request)");
  // A save after the defaults is the third record, and it wins.
  b->set_word(kN, rig_.N + 1);
  b->settings_ok(proto::SettingsAction::Save);
  EXPECT_EQ(b->last_log().rfind("settings: saved to flash, save 3 (", 0), 0u) << b->last_log();
  EXPECT_EQ(boot()->word(kN), uint32_t(rig_.N + 1));
}

TEST_F(Settings, RefusalsNameTheirStatusAndChangeNothing) {
  auto b = boot();
  b->set_word(kN, rig_.N + 2);
  b->settings_ok(proto::SettingsAction::Save);
  proto::Settings bad;
  bad.action = 3;
  const proto::Nack unknown = b->expect<proto::Nack>(bad);
  EXPECT_EQ(unknown.status, uint8_t(proto::StatusCode::OutOfRange));
  EXPECT_EQ(unknown.field, 0);
  // A run is active (an identification run needs no model): an erase would stall the loop.
  proto::IdentStart run;
  run.run_id = 7, run.signal = uint8_t(proto::IdentSignal::Steps), run.decimation = 1, run.amplitude = 0.5f;
  run.band_lo = 0.1f, run.band_hi = 1.0f, run.duration = 100000;
  b->expect<proto::Ack>(run);
  for (auto a : {proto::SettingsAction::Save, proto::SettingsAction::Defaults}) {
    const proto::Nack n = b->settings_nack(a);
    EXPECT_EQ(n.status, uint8_t(proto::StatusCode::WrongState));
    EXPECT_EQ(n.field, 0);
  }
  b->settings_ok(proto::SettingsAction::Report);  // allowed at any time
  b->expect<proto::Ack>(proto::RunStop{});
  // A flash that refuses: internal, a LOG, and the previous record stands.
  flash_.fail = true;
  b->set_word(kN, rig_.N + 4);
  const proto::Nack failed = b->settings_nack(proto::SettingsAction::Save);
  EXPECT_EQ(failed.status, uint8_t(proto::StatusCode::Internal));
  EXPECT_NE(b->last_log().find("previous settings stand"), std::string::npos) << b->last_log();
  flash_.fail = false;
  EXPECT_EQ(boot()->word(kN), uint32_t(rig_.N + 2));
}

// A record written by another build: entries out of order, a value this
// build refuses, an id it does not know. The rest is applied, the refused
// ones are named in the boot LOG.
TEST_F(Settings, ValuesThisBuildRefusesAreSkippedAndNamed) {
  std::vector<uint8_t> p = {1, 0, 0, 0};  // format 1, count later
  uint16_t count = 0;
  auto entry = [&](uint16_t id, uint8_t type, std::vector<uint32_t> words) {
    p.push_back(uint8_t(id)), p.push_back(uint8_t(id >> 8)), p.push_back(type), p.push_back(uint8_t(words.size()));
    for (uint32_t w : words)
      for (int i = 0; i < 4; ++i) p.push_back(uint8_t(w >> (8 * i)));
    ++count;
  };
  const uint8_t u8 = uint8_t(ParamType::U8);
  entry(kNc, u8, {4});   // above N until N is applied: tried again after it
  entry(kN1, u8, {3});
  entry(kN, u8, {rig_.N + 5u});
  float minus = -1.0f;
  uint32_t bits;
  std::memcpy(&bits, &minus, 4);
  entry(kS, uint8_t(ParamType::F32), {bits});  // below s's minimum
  entry(77, u8, {1});                          // no such id
  entry(kWatchdog, uint8_t(proto::ParamType::U16), {1500});
  p[2] = uint8_t(count), p[3] = uint8_t(count >> 8);
  {
    fw::SettingsStore store(flash_, 0, 1);
    ASSERT_EQ(store.save(p.data(), uint32_t(p.size())), fw::SettingsStatus::Ok);
  }
  auto b = boot();
  EXPECT_EQ(b->word(kN), rig_.N + 5u);
  EXPECT_EQ(b->word(kNc), 4u);
  EXPECT_EQ(b->word(kN1), 3u);
  EXPECT_EQ(b->f32(kS), rig_.s);
  EXPECT_EQ(b->word(kWatchdog), 1500u);
  ASSERT_FALSE(b->logs.empty());
  EXPECT_EQ(b->logs.front(),
            "settings: from flash, save 1 (4 values; 2 skipped, not accepted by this firmware: id 2 (out of range) "
            "id 77 (unknown id))");
}

TEST_F(Settings, ARecordOfAnotherFormatIsNotRead) {
  const uint8_t p[] = {2, 0, 0, 0};
  fw::SettingsStore store(flash_, 0, 1);
  ASSERT_EQ(store.save(p, sizeof p), fw::SettingsStatus::Ok);
  auto b = boot();
  EXPECT_EQ(b->word(kN), uint32_t(rig_.N));
  ASSERT_FALSE(b->logs.empty());
  EXPECT_EQ(b->logs.front(), "settings: built-in (save 1 is of a format this firmware does not read)");
}

}  // namespace
