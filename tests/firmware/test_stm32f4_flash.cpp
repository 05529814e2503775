// The STM32F4 flash driver (firmware/ports/stm32f4/flash.hpp) against a
// model of the part's flash interface as RM0390 3.5-3.8 describes it: the
// key sequence (a wrong one locks until reset), CR ignored while locked,
// PGSERR for an operation begun with an error flag set or a program
// without PG, PGPERR for another parallelism, PGAERR for an unaligned
// word, NOR programming (bits only cleared), a data cache that keeps
// serving what it read until it is reset while disabled, and power lost
// after any number of operations. QEMU models none of this (its
// netduinoplus2 maps flash as ROM), so this is where the driver is tested;
// the QEMU test checks that such an image claims no SETTINGS.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "firmware/core/settings_store.hpp"
#include "firmware/ports/stm32f4/flash.hpp"

namespace nlsoft::fw::stm32f4 {
namespace {

using namespace flash_if;

class InterfaceModel {
 public:
  static constexpr uint32_t kFlashBase = 0x08000000u, kFlashSize = 512u * 1024u;

  InterfaceModel() : mem_(kFlashSize) {
    for (auto& b : mem_) b = uint8_t(noise());  // a part's unwritten sectors hold anything
    power_on();
  }

  // A reset: registers as RM0390 gives them, the caches empty, the
  // operation a cut interrupted gone.
  void power_on() {
    cr_ = kLock, sr_ = 0, acr_ = kIcEn | kDcEn | 5u, key_state_ = 0, locked_until_reset_ = false;
    dead_ = false, busy_reads_ = 0, cache_.clear();
  }

  // --- the Io the driver sees ---
  uint32_t read32(uint32_t a) {
    if (a == kCr) return cr_;
    if (a == kAcr) return acr_;
    if (a == kSr) {
      if (busy_reads_ > 0 && !stuck_busy_) --busy_reads_;
      return sr_ | (busy_reads_ > 0 || stuck_busy_ ? kBsy : 0u);
    }
    if (in_flash(a)) {
      uint8_t b[4];
      read_bytes(a, b, 4);
      return uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
    }
    violation("read of an unknown register");
    return 0;
  }
  void write32(uint32_t a, uint32_t v) {
    if (dead_) return;
    if (a == kKeyr) return key(v);
    if (a == kSr) {
      sr_ &= ~(v & (kErrors | kEop));  // write 1 to clear
      return;
    }
    if (a == kAcr) return acr(v);
    if (a == kCr) return control(v);
    if (in_flash(a)) return program_word(a, v);
    violation("write to an unknown register");
  }
  void read_bytes(uint32_t a, uint8_t* out, size_t n) {
    for (size_t i = 0; i < n; ++i) {
      const uint32_t at = a + uint32_t(i);
      if (!in_flash(at)) {
        violation("read outside the flash");
        out[i] = 0;
        continue;
      }
      const uint32_t line = at & ~15u;  // the data cache holds 128-bit lines
      if (acr_ & kDcEn) {
        auto it = cache_.find(line);
        if (it == cache_.end()) it = cache_.emplace(line, std::vector<uint8_t>(&mem_[line - kFlashBase], &mem_[line - kFlashBase] + 16)).first;
        out[i] = it->second[at - line];
      } else {
        out[i] = mem_[at - kFlashBase];
      }
    }
  }
  uint32_t erase_spins() { return 1000; }
  uint32_t program_spins() { return 100; }
  void erase_begins() {
    ++long_watchdog_, ++widened;
    if (busy_reads_ > 0) violation("watchdog widened after the erase began");
  }
  void erase_ends() { --long_watchdog_; }

  // --- what the test sets and reads ---
  // Power is lost after `ops` more erases or programmed words.
  void cut_after(long ops) { ops_left_ = ops; }
  void fail_next_erase(uint32_t flag) { fail_erase_ = flag; }
  // The next erase starts and never ends.
  void stick_busy() { stick_on_start_ = true; }
  void set_error_flag(uint32_t flag) { sr_ |= flag; }
  bool locked() const { return (cr_ & kLock) != 0; }
  bool dead() const { return dead_; }
  int long_watchdog() const { return long_watchdog_; }
  int erases = 0, cache_resets = 0, widened = 0;
  std::vector<std::string> violations;
  uint8_t at(uint32_t a) const { return mem_[a - kFlashBase]; }

 private:
  static bool in_flash(uint32_t a) { return a >= kFlashBase && a - kFlashBase < kFlashSize; }
  void violation(const char* what) { violations.emplace_back(what); }

  bool power_lasts() {
    if (ops_left_ < 0) return true;
    if (ops_left_ == 0) return dead_ = true, false;
    --ops_left_;
    return true;
  }

  void key(uint32_t v) {
    if (locked_until_reset_ || !(cr_ & kLock)) {
      violation("key written to an unlocked or blocked interface");
      locked_until_reset_ = true;
      return;
    }
    if (key_state_ == 0 && v == kKey1) {
      key_state_ = 1;
    } else if (key_state_ == 1 && v == kKey2) {
      key_state_ = 0, cr_ &= ~kLock;
    } else {
      violation("wrong key sequence");
      locked_until_reset_ = true;
    }
  }

  void acr(uint32_t v) {
    if ((v & kDcRst) && (v & kDcEn)) violation("data cache reset while enabled");
    if ((v & kIcRst) && (v & kIcEn)) violation("instruction cache reset while enabled");
    if ((v & kDcRst) && !(v & kDcEn)) cache_.clear(), ++cache_resets;
    acr_ = v;
  }

  void control(uint32_t v) {
    if (cr_ & kLock) {  // ignored; setting LOCK again is what a lock does anyway
      if (v != kLock) violation("CR written while locked");
      return;
    }
    if (busy_reads_ > 0) violation("CR written while busy");
    cr_ = v & ~kStrt;
    if (!(v & kStrt)) return;
    if (!(v & kSer)) return violation("STRT without SER");
    if (v & kPg) return (void)(sr_ |= kPgsErr);
    if (sr_ & kErrors) return (void)(sr_ |= kPgsErr);  // an error flag left set refuses the operation
    const int snb = int((v >> kSnbShift) & 0xFu);
    if (snb >= kSectorCount) return violation("erase of a sector the part lacks");
    if (fail_erase_) {
      sr_ |= fail_erase_, fail_erase_ = 0;
      return;
    }
    uint8_t* s = &mem_[kSectors[snb].base - kFlashBase];
    if (!power_lasts()) {  // cut mid-erase: the sector holds anything
      for (uint32_t i = 0; i < kSectors[snb].size; ++i) s[i] = uint8_t(noise());
      return;
    }
    std::memset(s, 0xFF, kSectors[snb].size);
    ++erases;
    busy_reads_ = 5;
    stuck_busy_ = stick_on_start_;
  }

  void program_word(uint32_t a, uint32_t v) {
    if ((cr_ & kLock) || !(cr_ & kPg)) return (void)(sr_ |= kPgsErr);
    if (busy_reads_ > 0) violation("program while busy");
    if (sr_ & kErrors) return (void)(sr_ |= kPgsErr);
    if ((cr_ & (3u << 8)) != kPsizeX32) return (void)(sr_ |= kPgpErr);
    if (a & 3u) return (void)(sr_ |= kPgaErr);
    uint8_t* p = &mem_[a - kFlashBase];
    const bool lasts = power_lasts();
    for (int b = 0; b < 4; ++b) {
      const uint8_t byte = uint8_t(v >> (8 * b));
      p[b] &= lasts ? byte : uint8_t(byte | noise());  // cut mid-word: some of its bits cleared
    }
    busy_reads_ = 2;
  }

  uint32_t noise() {  // xorshift32: the same noise every run
    rng_ ^= rng_ << 13, rng_ ^= rng_ >> 17, rng_ ^= rng_ << 5;
    return rng_;
  }

  std::vector<uint8_t> mem_;
  uint32_t cr_ = kLock, sr_ = 0, acr_ = 0, fail_erase_ = 0;
  int key_state_ = 0, busy_reads_ = 0, long_watchdog_ = 0;
  bool locked_until_reset_ = false, dead_ = false, stuck_busy_ = false, stick_on_start_ = false;
  long ops_left_ = -1;
  std::map<uint32_t, std::vector<uint8_t>> cache_;
  uint32_t rng_ = 0x2545F491u;
};

std::vector<uint8_t> payload(size_t n, uint8_t salt) {
  std::vector<uint8_t> p(n);
  for (size_t i = 0; i < n; ++i) p[i] = uint8_t(i * 31u + salt);
  return p;
}

struct Board {
  InterfaceModel part;
  Flash<InterfaceModel> flash{part};
  SettingsStore store{flash, kSettingsSectorA, kSettingsSectorB};
  uint8_t buf[2048] = {};

  SettingsStatus save(const std::vector<uint8_t>& p) {
    return store.save(p.data(), uint32_t(p.size()));
  }
  // The payload of the newest record; empty when none checks.
  std::vector<uint8_t> load(SettingsRecord* rec = nullptr) {
    SettingsRecord r;
    if (store.load(buf, sizeof buf, r) != SettingsStatus::Ok) return {};
    if (rec) *rec = r;
    return std::vector<uint8_t>(buf, buf + r.length);
  }
};

TEST(Stm32f4Flash, SettingsSectorsAreTheTwoTheLinkerScriptKeepsFree) {
  EXPECT_EQ(kSectors[kSettingsSectorA].base, 0x08004000u);
  EXPECT_EQ(kSectors[kSettingsSectorB].base + kSectors[kSettingsSectorB].size, 0x0800C000u);
  uint32_t total = 0;
  for (const Sector& s : kSectors) {
    EXPECT_EQ(s.base, 0x08000000u + total);
    total += s.size;
  }
  EXPECT_EQ(total, 512u * 1024u);
}

TEST(Stm32f4Flash, SaveAndLoadFollowThePartsRules) {
  Board b;
  ASSERT_TRUE(b.flash.present());
  const auto first = payload(301, 1), second = payload(122, 2);  // lengths that are not whole words
  ASSERT_EQ(b.save(first), SettingsStatus::Ok);
  EXPECT_EQ(b.load(), first);
  ASSERT_EQ(b.save(second), SettingsStatus::Ok);
  SettingsRecord rec;
  EXPECT_EQ(b.load(&rec), second);
  EXPECT_EQ(rec.seq, 2u);
  EXPECT_EQ(rec.sector, 1);  // the second of the two: the first still holds record 1
  EXPECT_EQ(b.part.erases, 2);
  EXPECT_TRUE(b.part.violations.empty()) << b.part.violations.front();
  EXPECT_TRUE(b.part.locked());
  EXPECT_EQ(b.part.long_watchdog(), 0);
  EXPECT_GE(b.part.cache_resets, 2);
  // Nothing outside the two sectors was touched: sector 0's first word and sector 3's.
  InterfaceModel fresh;
  EXPECT_EQ(b.part.at(0x08000000u), fresh.at(0x08000000u));
  EXPECT_EQ(b.part.at(0x0800C000u), fresh.at(0x0800C000u));
}

TEST(Stm32f4Flash, ReadBackAfterASaveSeesTheFlashNotTheCache) {
  // A load fills the data cache with record 1's lines; the next save
  // erases and programs those lines. Its read-back and the load after it
  // must see the new bytes: the driver resets the cache after each operation.
  Board b;
  ASSERT_EQ(b.save(payload(200, 1)), SettingsStatus::Ok);
  ASSERT_EQ(b.save(payload(200, 2)), SettingsStatus::Ok);
  ASSERT_EQ(b.load(), payload(200, 2));
  ASSERT_EQ(b.save(payload(200, 3)), SettingsStatus::Ok);  // over sector A, whose old lines were read
  EXPECT_EQ(b.load(), payload(200, 3));
}

TEST(Stm32f4Flash, APowerCutAtEveryWordLeavesTheOldOrTheNewSettings) {
  const auto old_p = payload(97, 7), new_p = payload(211, 9);
  long cuts = 0, became_new = 0;
  for (long ops = 0;; ++ops) {
    Board b;
    ASSERT_EQ(b.save(old_p), SettingsStatus::Ok);
    b.part.cut_after(ops);
    const SettingsStatus s = b.save(new_p);
    const bool cut = b.part.dead();
    b.part.power_on();
    const auto now = b.load();
    ASSERT_TRUE(now == old_p || now == new_p) << "cut after " << ops << " operations: neither record loads";
    if (!cut) {
      EXPECT_EQ(s, SettingsStatus::Ok);
      EXPECT_EQ(now, new_p);
      break;
    }
    ++cuts;
    became_new += now == new_p;
    EXPECT_TRUE(b.part.violations.empty()) << b.part.violations.front();
  }
  // 1 erase + 53 payload words + 4 header words + 1 commit word.
  EXPECT_EQ(cuts, 1 + 53 + 4 + 1);
  EXPECT_EQ(became_new, 0);  // only the commit word's completion makes the new record
}

TEST(Stm32f4Flash, AnErrorFlagFailsTheSaveAndThePreviousRecordStands) {
  for (uint32_t flag : {kWrpErr, kOpErr}) {
    Board b;
    ASSERT_EQ(b.save(payload(64, 1)), SettingsStatus::Ok);
    b.part.fail_next_erase(flag);
    EXPECT_EQ(b.save(payload(64, 2)), SettingsStatus::FlashFailed);
    EXPECT_EQ(b.load(), payload(64, 1));
    EXPECT_TRUE(b.part.locked());
    // The flag is cleared before the next operation: a later save succeeds.
    EXPECT_EQ(b.save(payload(64, 3)), SettingsStatus::Ok);
    EXPECT_EQ(b.load(), payload(64, 3));
    EXPECT_TRUE(b.part.violations.empty()) << b.part.violations.front();
  }
}

TEST(Stm32f4Flash, AFlagLeftFromBeforeBootIsClearedFirst) {
  Board b;
  b.part.set_error_flag(kPgsErr | kPgpErr);
  EXPECT_EQ(b.save(payload(40, 1)), SettingsStatus::Ok);
  EXPECT_EQ(b.load(), payload(40, 1));
}

TEST(Stm32f4Flash, AnEraseThatNeverEndsFailsWithinItsBound) {
  Board b;
  b.part.stick_busy();
  EXPECT_FALSE(b.flash.erase(kSettingsSectorA));
  EXPECT_EQ(b.part.widened, 1);          // the erase ran under the long watchdog period
  EXPECT_EQ(b.part.long_watchdog(), 0);  // and it is back to its half second
}

TEST(Stm32f4Flash, RefusesSectorsAndAddressesThePartLacks) {
  Board b;
  const uint8_t word[4] = {0, 0, 0, 0};
  EXPECT_FALSE(b.flash.erase(-1));
  EXPECT_FALSE(b.flash.erase(kSectorCount));
  EXPECT_FALSE(b.flash.program(0x08080000u, word, 4));
  EXPECT_FALSE(b.flash.program(0x0807FFFEu, word, 4));  // runs past the end
  EXPECT_EQ(b.part.erases, 0);
  EXPECT_TRUE(b.part.violations.empty()) << b.part.violations.front();
}

TEST(Stm32f4Flash, AnUnalignedProgramLeavesItsNeighboursAlone) {
  Board b;
  ASSERT_TRUE(b.flash.erase(kSettingsSectorA));
  const uint32_t base = kSectors[kSettingsSectorA].base;
  const uint8_t bytes[5] = {0x11, 0x22, 0x33, 0x44, 0x55};
  ASSERT_TRUE(b.flash.program(base + 3, bytes, sizeof bytes));
  uint8_t back[10];
  b.flash.read(base, back, sizeof back);
  const uint8_t want[10] = {0xFF, 0xFF, 0xFF, 0x11, 0x22, 0x33, 0x44, 0x55, 0xFF, 0xFF};
  EXPECT_EQ(0, std::memcmp(back, want, sizeof want));
  EXPECT_TRUE(b.part.violations.empty()) << b.part.violations.front();
}

// What QEMU's netduinoplus2 gives at 0x40023C00: registers that read 0 and
// ignore writes.
struct NoInterface {
  uint32_t read32(uint32_t) { return 0; }
  void write32(uint32_t, uint32_t) {}
  void read_bytes(uint32_t, uint8_t* out, size_t n) { std::memset(out, 0, n); }
  uint32_t erase_spins() { return 10; }
  uint32_t program_spins() { return 10; }
  void erase_begins() {}
  void erase_ends() {}
};

TEST(Stm32f4Flash, AnInterfaceThatDoesNotAnswerIsNotPresent) {
  NoInterface none;
  Flash<NoInterface> absent(none);
  EXPECT_FALSE(absent.present());
  Board b;
  EXPECT_TRUE(b.flash.present());
  EXPECT_TRUE(b.part.locked());
}

}  // namespace
}  // namespace nlsoft::fw::stm32f4
