#pragma once
// The STM32F4's embedded flash as the settings store's FlashPart: sector
// erase and 32-bit programming through the flash interface (RM0390 3.5-3.8;
// RM0368 and RM0383 give the F401 and F411 the same registers and sectors).
//
// - Parallelism x32 (PSIZE 10): the Nucleo runs at 3.3 V, inside x32's
//   2.7-3.6 V, and x32 erases a 16 KB sector in 250 ms (500 ms at most),
//   within PROTOCOL.md 10's 1000 ms for SETTINGS.
// - The interface is unlocked for one operation and locked again after it,
//   so a stray write elsewhere in the firmware cannot program the part.
// - Error flags are cleared before each operation (the part refuses one
//   that starts with a flag set: PGSERR) and read after it; any flag fails
//   the operation, and the settings store then keeps the previous record.
// - The ART accelerator's caches are reset after each operation: a
//   read-back through the data cache would otherwise see the bytes from
//   before the erase (RM0390 3.5.2, "the caches must be flushed").
// - An erase stalls the CPU for its whole duration whenever code is fetched
//   from flash (RM0390 3.5.4), so the part's watchdog must outlast it:
//   Io::erase_begins/erase_ends bracket the erase for that.
//
// Io is the register access: MMIO on the part (flash.cpp), a model of the
// interface in the host test (tests/firmware/test_stm32f4_flash.cpp). It
// gives read32/write32 (registers and flash words alike), read_bytes of
// flash, erase_spins/program_spins (poll bounds of at least the part's
// longest erase and program time) and erase_begins/erase_ends.
//
// Hand-written: ST's HAL and libopencm3 do this, but neither is packaged
// for arm-none-eabi in Debian, and the port takes no vendor code (regs.hpp).
#include <cstddef>
#include <cstdint>

#include "firmware/core/settings_store.hpp"

namespace nlsoft::fw::stm32f4 {

namespace flash_if {
constexpr uint32_t kBase = 0x40023C00u;
constexpr uint32_t kAcr = kBase + 0x00, kKeyr = kBase + 0x04, kSr = kBase + 0x0C, kCr = kBase + 0x10;
constexpr uint32_t kKey1 = 0x45670123u, kKey2 = 0xCDEF89ABu;
// FLASH_ACR: instruction and data cache enables and resets.
constexpr uint32_t kIcEn = 1u << 9, kDcEn = 1u << 10, kIcRst = 1u << 11, kDcRst = 1u << 12;
// FLASH_SR: end of operation, the error flags (write 1 to clear), busy.
constexpr uint32_t kEop = 1u << 0, kOpErr = 1u << 1, kWrpErr = 1u << 4, kPgaErr = 1u << 5, kPgpErr = 1u << 6,
                   kPgsErr = 1u << 7, kRdErr = 1u << 8, kBsy = 1u << 16;
constexpr uint32_t kErrors = kOpErr | kWrpErr | kPgaErr | kPgpErr | kPgsErr | kRdErr;
// FLASH_CR: program, sector erase, sector number (bits 3-6), parallelism
// (bits 8-9; 2 = x32), start, lock.
constexpr uint32_t kPg = 1u << 0, kSer = 1u << 1, kSnbShift = 3, kPsizeX32 = 2u << 8, kStrt = 1u << 16,
                   kLock = 1u << 31;
}  // namespace flash_if

// The single-bank 512 KB parts (F401RE, F411RE, F446RE): four 16 KB
// sectors, one of 64 KB, three of 128 KB.
struct Sector {
  uint32_t base, size;
};
constexpr Sector kSectors[] = {
    {0x08000000u, 16384u},  {0x08004000u, 16384u},  {0x08008000u, 16384u},  {0x0800C000u, 16384u},
    {0x08010000u, 65536u},  {0x08020000u, 131072u}, {0x08040000u, 131072u}, {0x08060000u, 131072u},
};
constexpr int kSectorCount = int(sizeof kSectors / sizeof kSectors[0]);

// The two 16 KB sectors the settings live in. The linker script keeps
// code out of them (stm32f4.ld: the vector table in sector 0, the rest
// from sector 3).
constexpr int kSettingsSectorA = 1, kSettingsSectorB = 2;

template <class Io>
class Flash final : public FlashPart {
 public:
  constexpr explicit Flash(Io& io) : io_(io) {}

  // Whether the part has a flash interface that answers. FLASH_CR reads
  // LOCK set at reset and after a lock; an emulator that models no
  // interface (QEMU's netduinoplus2) reads 0 and ignores writes, and an
  // image must not claim settings it cannot keep there.
  bool present() {
    lock();
    return (io_.read32(flash_if::kCr) & flash_if::kLock) != 0;
  }

  uint32_t sector_base(int sector) const override { return valid(sector) ? kSectors[sector].base : 0; }
  uint32_t sector_size(int sector) const override { return valid(sector) ? kSectors[sector].size : 0; }

  bool erase(int sector) override {
    using namespace flash_if;
    if (!valid(sector) || !begin()) return false;
    const uint32_t cr = kPsizeX32 | kSer | uint32_t(sector) << kSnbShift;
    io_.write32(kCr, cr);
    io_.erase_begins();
    io_.write32(kCr, cr | kStrt);
    const bool idle = wait_idle(io_.erase_spins());
    io_.erase_ends();
    return end(idle);
  }

  // Programs len bytes at addr, a word at a time; the bytes of a word
  // outside [addr, addr + len) are programmed as 0xFF, which leaves them as
  // they are (programming only clears bits).
  bool program(uint32_t addr, const uint8_t* data, size_t len) override {
    using namespace flash_if;
    if (len == 0) return true;
    if (!inside(addr, len) || !begin()) return false;
    io_.write32(kCr, kPsizeX32 | kPg);
    bool ok = true;
    const uint32_t first = addr & ~3u, last = uint32_t(addr + len - 1) & ~3u;
    for (uint32_t word = first; ok && word <= last; word += 4) {
      uint32_t v = 0;
      for (uint32_t b = 0; b < 4; ++b) {
        const uint32_t at = word + b;
        const uint8_t byte = at >= addr && at - addr < len ? data[at - addr] : 0xFFu;
        v |= uint32_t(byte) << (8 * b);
      }
      io_.write32(word, v);
      ok = wait_idle(io_.program_spins()) && (io_.read32(kSr) & kErrors) == 0;
    }
    return end(ok);
  }

  void read(uint32_t addr, uint8_t* out, size_t len) const override {
    if (inside(addr, len)) return io_.read_bytes(addr, out, len);
    for (size_t i = 0; i < len; ++i) out[i] = 0xFFu;  // outside the part: reads as erased, never checks
  }

 private:
  static bool valid(int sector) { return sector >= 0 && sector < kSectorCount; }
  static bool inside(uint32_t addr, size_t len) {
    const uint32_t lo = kSectors[0].base, hi = kSectors[kSectorCount - 1].base + kSectors[kSectorCount - 1].size;
    return addr >= lo && addr <= hi && len <= size_t(hi - addr);
  }

  bool wait_idle(uint32_t spins) {
    for (uint32_t i = 0; i < spins; ++i)
      if (!(io_.read32(flash_if::kSr) & flash_if::kBsy)) return true;
    return false;
  }

  // Unlocked, idle, no error flag left from before.
  bool begin() {
    using namespace flash_if;
    if (!wait_idle(io_.program_spins())) return false;
    if (io_.read32(kCr) & kLock) {
      io_.write32(kKeyr, kKey1);
      io_.write32(kKeyr, kKey2);
      if (io_.read32(kCr) & kLock) return false;  // a wrong sequence locks it until reset
    }
    io_.write32(kSr, kErrors | kEop);
    return true;
  }

  // The operation's outcome; the interface locked and the caches reset.
  bool end(bool ok) {
    using namespace flash_if;
    ok = ok && (io_.read32(kSr) & kErrors) == 0;
    io_.write32(kSr, kErrors | kEop);
    lock();
    flush_caches();
    return ok;
  }

  void lock() { io_.write32(flash_if::kCr, flash_if::kLock); }

  // A cache is reset only while it is disabled (RM0390 3.5.2).
  void flush_caches() {
    using namespace flash_if;
    const uint32_t acr = io_.read32(kAcr);
    const uint32_t on = acr & (kIcEn | kDcEn);
    io_.write32(kAcr, acr & ~on);
    io_.write32(kAcr, (acr & ~on) | kIcRst | kDcRst);
    io_.write32(kAcr, acr & ~on);
    io_.write32(kAcr, acr);
  }

  Io& io_;
};

}  // namespace nlsoft::fw::stm32f4
