// Saved settings against a model of a NOR flash part (erase to 0xFF,
// programming only clears bits) that loses power after any number of
// operations: a cut at every byte of a save leaves the settings of the
// last finished save or the new ones, never neither, never older ones.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "firmware/core/settings_store.hpp"

namespace nlsoft::fw {
namespace {

class FlashModel final : public FlashPart {
 public:
  explicit FlashModel(uint32_t sector_bytes, int sectors = 2)
      : size_(sector_bytes), mem_(size_t(sector_bytes) * size_t(sectors), 0xFF) {
    // What an unused part holds is not always 0xFF: make the first boot see noise.
    for (size_t i = 0; i < mem_.size(); ++i) mem_[i] = uint8_t(next());
  }

  uint32_t sector_base(int sector) const override { return uint32_t(sector) * size_; }
  uint32_t sector_size(int) const override { return size_; }

  bool erase(int sector) override {
    if (!step()) {  // cut during the erase: the sector holds anything
      for (uint32_t i = 0; i < size_; ++i) mem_[sector_base(sector) + i] = uint8_t(next());
      return false;
    }
    std::memset(&mem_[sector_base(sector)], 0xFF, size_);
    ++erases;
    return true;
  }
  bool program(uint32_t addr, const uint8_t* data, size_t len) override {
    for (size_t i = 0; i < len; ++i) {
      if (!step()) {  // cut while programming this byte: some of its bits cleared
        mem_[addr + i] &= uint8_t(data[i] | next());
        return false;
      }
      mem_[addr + i] &= data[i];
    }
    return true;
  }
  void read(uint32_t addr, uint8_t* out, size_t len) const override { std::memcpy(out, &mem_[addr], len); }

  // Power is lost after `ops` more operations (an erase or one byte); -1: never.
  void cut_after(long ops) { left_ = ops, dead_ = false; }
  std::vector<uint8_t>& memory() { return mem_; }
  int erases = 0;

 private:
  bool step() {
    if (dead_) return false;
    if (left_ == 0) return dead_ = true, false;
    if (left_ > 0) --left_;
    return true;
  }
  uint32_t next() {  // xorshift32: the same noise every run
    rng_ ^= rng_ << 13, rng_ ^= rng_ >> 17, rng_ ^= rng_ << 5;
    return rng_;
  }

  uint32_t size_;
  std::vector<uint8_t> mem_;
  long left_ = -1;
  bool dead_ = false;
  uint32_t rng_ = 0x2545F491u;
};

std::vector<uint8_t> settings(int which, size_t len = 120) {
  std::vector<uint8_t> v(len);
  for (size_t i = 0; i < len; ++i) v[i] = uint8_t(which * 37 + int(i) * 11);
  return v;
}

// What a boot after the cut loads: the payload, or empty for none.
struct Loaded {
  SettingsStatus status;
  std::vector<uint8_t> bytes;
};
Loaded boot(FlashModel& flash) {
  flash.cut_after(-1);
  SettingsStore store(flash, 0, 1);
  uint8_t buf[256];
  SettingsRecord r;
  Loaded l{store.load(buf, sizeof buf, r), {}};
  if (l.status == SettingsStatus::Ok) l.bytes.assign(buf, buf + r.length);
  return l;
}

SettingsStatus save(FlashModel& flash, const std::vector<uint8_t>& v) {
  SettingsStore store(flash, 0, 1);
  return store.save(v.data(), uint32_t(v.size()));
}

TEST(SettingsStore, NothingSavedLoadsNothing) {
  FlashModel flash(256);
  EXPECT_EQ(boot(flash).status, SettingsStatus::None);
}

TEST(SettingsStore, TheLastSaveWinsAndSavesAlternateSectors) {
  FlashModel flash(256);
  for (int k = 1; k <= 5; ++k) {
    ASSERT_EQ(save(flash, settings(k)), SettingsStatus::Ok);
    const Loaded l = boot(flash);
    ASSERT_EQ(l.status, SettingsStatus::Ok);
    EXPECT_EQ(l.bytes, settings(k));
  }
  EXPECT_EQ(flash.erases, 5);
  // The two sectors hold the last two saves: 4 and 5.
  SettingsStore store(flash, 0, 1);
  uint8_t buf[256];
  SettingsRecord r;
  ASSERT_EQ(store.load(buf, sizeof buf, r), SettingsStatus::Ok);
  EXPECT_EQ(r.seq, 5u);
  EXPECT_EQ(r.sector, 0);  // 1 in sector 0, 2 in 1, ..., 5 in 0
}

TEST(SettingsStore, ACutAtEveryStepOfASaveLeavesTheOldOrTheNewSettings) {
  // Steps of a save of 120 bytes: the erase, 120 payload bytes, 16 header
  // bytes, 4 commit bytes.
  const long steps = 1 + 120 + 16 + 4;
  for (int before = 0; before < 2; ++before) {  // the old settings in sector 0 or in sector 1
    for (long cut = 0; cut <= steps; ++cut) {
      SCOPED_TRACE("old settings after " + std::to_string(before + 1) + " saves, cut after " + std::to_string(cut) +
                   " steps");
      FlashModel flash(256);
      for (int k = 0; k <= before; ++k) ASSERT_EQ(save(flash, settings(10 + k)), SettingsStatus::Ok);
      const std::vector<uint8_t> old = settings(10 + before), fresh = settings(99);
      flash.cut_after(cut);
      const SettingsStatus s = save(flash, fresh);
      const Loaded l = boot(flash);
      ASSERT_EQ(l.status, SettingsStatus::Ok);
      if (cut < steps) {
        EXPECT_EQ(s, SettingsStatus::FlashFailed);
        EXPECT_EQ(l.bytes, old) << "a save cut before its commit word was whole is never loaded";
      } else {
        EXPECT_EQ(s, SettingsStatus::Ok);
        EXPECT_EQ(l.bytes, fresh);
      }
    }
  }
}

// Many saves, each cut at some step or not: a boot always finds the last
// finished save's settings or the one in flight, never an older one.
TEST(SettingsStore, RepeatedCutsNeverGoBackPastTheLastFinishedSave) {
  FlashModel flash(256);
  ASSERT_EQ(save(flash, settings(1)), SettingsStatus::Ok);
  std::vector<uint8_t> finished = settings(1);
  uint32_t r = 12345;
  for (int k = 2; k < 400; ++k) {
    r = r * 1103515245u + 12345u;
    const long cut = (r >> 16) % 200;  // beyond 141 steps: the save finishes
    const std::vector<uint8_t> fresh = settings(k, 1 + (r >> 8) % 200);
    flash.cut_after(cut);
    const SettingsStatus s = save(flash, fresh);
    const Loaded l = boot(flash);
    ASSERT_EQ(l.status, SettingsStatus::Ok) << "save " << k;
    if (s == SettingsStatus::Ok) {
      EXPECT_EQ(l.bytes, fresh) << "save " << k;
      finished = fresh;
    } else {
      EXPECT_TRUE(l.bytes == finished || l.bytes == fresh) << "save " << k;
      finished = l.bytes;  // what the board now runs with
    }
  }
}

TEST(SettingsStore, ACorruptRecordIsNeverLoaded) {
  FlashModel flash(256);
  ASSERT_EQ(save(flash, settings(1)), SettingsStatus::Ok);
  ASSERT_EQ(save(flash, settings(2)), SettingsStatus::Ok);  // in sector 1
  flash.memory()[256 + SettingsStore::kHeader + 7] ^= 0x04;  // one bit of its payload
  Loaded l = boot(flash);
  ASSERT_EQ(l.status, SettingsStatus::Ok);
  EXPECT_EQ(l.bytes, settings(1));
  flash.memory()[SettingsStore::kHeader] ^= 0x80;  // and the older one's
  EXPECT_EQ(boot(flash).status, SettingsStatus::None);
}

TEST(SettingsStore, TheDefaultsAreARecordToo) {
  FlashModel flash(256);
  ASSERT_EQ(save(flash, settings(1)), SettingsStatus::Ok);
  ASSERT_EQ(save(flash, {}), SettingsStatus::Ok);
  const Loaded l = boot(flash);
  ASSERT_EQ(l.status, SettingsStatus::Ok);
  EXPECT_TRUE(l.bytes.empty()) << "length 0: the built-in defaults";
}

TEST(SettingsStore, SettingsLargerThanASectorAreRefusedBeforeAnythingIsErased) {
  FlashModel flash(256);
  ASSERT_EQ(save(flash, settings(1)), SettingsStatus::Ok);
  const std::vector<uint8_t> before = flash.memory();
  EXPECT_EQ(save(flash, settings(2, 256 - SettingsStore::kHeader + 1)), SettingsStatus::TooLarge);
  EXPECT_EQ(flash.memory(), before);
  EXPECT_EQ(boot(flash).bytes, settings(1));
}

// The sequence number wraps: 0 is newer than 0xFFFFFFFF.
TEST(SettingsStore, TheSequenceNumberWraps) {
  FlashModel flash(256);
  auto forge = [&](int sector, uint32_t seq, const std::vector<uint8_t>& v) {
    uint8_t* p = &flash.memory()[size_t(sector) * 256];
    std::memset(p, 0xFF, 256);
    auto put = [](uint8_t* q, uint32_t x) {
      for (int i = 0; i < 4; ++i) q[i] = uint8_t(x >> (8 * i));
    };
    put(p, SettingsStore::kMagic);
    put(p + 4, seq);
    put(p + 8, uint32_t(v.size()));
    Crc32 crc;
    crc.update(p + 4, 8);
    crc.update(v.data(), v.size());
    put(p + 12, crc.value());
    put(p + 16, SettingsStore::kCommit);
    std::memcpy(p + SettingsStore::kHeader, v.data(), v.size());
  };
  forge(0, 0xFFFFFFFFu, settings(1));
  forge(1, 0u, settings(2));
  EXPECT_EQ(boot(flash).bytes, settings(2));
  forge(0, 1u, settings(3));
  EXPECT_EQ(boot(flash).bytes, settings(3));
}

}  // namespace
}  // namespace nlsoft::fw
