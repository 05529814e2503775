#pragma once
// Settings that survive a power cut at any byte: two flash sectors, each
// holding at most one record, and the newest record that checks wins.
//
// A record, at the start of its sector:
//   offset 0   u32 magic 'NLSS'         (0x53534C4E little-endian)
//   offset 4   u32 seq                  one more than the record it replaces
//   offset 8   u32 length               payload bytes; 0: "the built-in defaults"
//   offset 12  u32 crc                  CRC-32 of bytes 4..11 and the payload
//   offset 16  u32 commit 0x0000A55A    written last, alone
//   offset 32  payload
// A save erases the sector that does not hold the newest good record,
// programs the payload, then the header, then the commit word. NOR flash
// programs by clearing bits, so a cut anywhere before the commit word is
// whole leaves a commit that is not 0x0000A55A (an erased 0xFFFFFFFF or
// some bits of it): the record is ignored and the other sector's, untouched,
// still wins. A cut during the erase leaves that sector unreadable, which
// is the same. The newest record is only ever replaced by writing the other
// sector, so there is always one good record once one save has finished.
//
// Hand-written: the settings libraries that do this (Zephyr's NVS, mbed's
// KVStore) come with their RTOS's flash API; this is 100 lines over the
// three operations every part has.
#include <cstddef>
#include <cstdint>

#include "shared/crc32.hpp"

namespace nlsoft::fw {

// What a part's flash allows. Erase sets a sector to 0xFF; program can only
// clear bits (the part's rule: programming a 1 over a 0 leaves the 0).
class FlashPart {
 public:
  virtual uint32_t sector_base(int sector) const = 0;
  virtual uint32_t sector_size(int sector) const = 0;
  virtual bool erase(int sector) = 0;
  virtual bool program(uint32_t addr, const uint8_t* data, size_t len) = 0;
  virtual void read(uint32_t addr, uint8_t* out, size_t len) const = 0;

 protected:
  // Not virtual: a virtual destructor brings operator delete, and with it
  // the heap, into every image; nothing is destroyed through a FlashPart.
  ~FlashPart() = default;
};

enum class SettingsStatus : uint8_t {
  Ok = 0,
  None,       // load: no record checks (never saved, or both torn)
  TooLarge,   // save: the payload does not fit a sector
  FlashFailed // save: erase, program or the read-back failed; the previous record stands
};

struct SettingsRecord {
  int sector = -1;       // which of the two (0, 1); -1: none
  uint32_t seq = 0;
  uint32_t length = 0;   // 0: the built-in defaults were chosen
};

class SettingsStore {
 public:
  static constexpr uint32_t kMagic = 0x53534C4Eu;  // "NLSS"
  static constexpr uint32_t kCommit = 0x0000A55Au;
  static constexpr uint32_t kHeader = 32;

  // sectors a and b of `flash`, reserved for the settings.
  SettingsStore(FlashPart& flash, int a, int b) : flash_(flash), sector_{a, b} {}

  // The newest record that checks, and its payload copied into buf (cap
  // bytes; a longer record does not check). None when there is none.
  SettingsStatus load(uint8_t* buf, size_t cap, SettingsRecord& out) const {
    out = SettingsRecord{};
    SettingsRecord r[2];
    bool ok[2];
    for (int i = 0; i < 2; ++i) ok[i] = check(i, buf, cap, r[i]);
    const int pick = !ok[0] && !ok[1] ? -1 : !ok[1] ? 0 : !ok[0] ? 1 : (newer(r[1].seq, r[0].seq) ? 1 : 0);
    if (pick < 0) return SettingsStatus::None;
    out = r[pick];
    if (pick == 0 && buf) check(0, buf, cap, out);  // sector 1's check, read last, may have left its bytes in buf
    return SettingsStatus::Ok;
  }

  // The newest record that checks, its payload read only for the CRC:
  // no buffer of a record's size.
  SettingsStatus newest(SettingsRecord& out) const { return load(nullptr, 0, out); }

  // Writes payload (length 0: a record that says "built-in defaults") as
  // the newest record, and reads it back; `saved`, if given, is then that
  // record. On any failure the newest record is the one before.
  SettingsStatus save(const uint8_t* payload, uint32_t length, SettingsRecord* saved = nullptr) {
    SettingsRecord last;
    const bool any = newest(last) == SettingsStatus::Ok;
    const int target_sector = any && last.sector == 0 ? 1 : 0;
    if (uint64_t(kHeader) + length > flash_.sector_size(sector_[target_sector])) return SettingsStatus::TooLarge;
    const uint32_t seq = any ? last.seq + 1u : 1u;
    const uint32_t base = flash_.sector_base(sector_[target_sector]);
    uint8_t head[16];
    put32(head + 0, kMagic);
    put32(head + 4, seq);
    put32(head + 8, length);
    Crc32 crc;
    crc.update(head + 4, 8);
    if (length) crc.update(payload, length);
    put32(head + 12, crc.value());
    uint8_t commit[4];
    put32(commit, kCommit);
    if (!flash_.erase(sector_[target_sector])) return SettingsStatus::FlashFailed;
    if (length && !flash_.program(base + kHeader, payload, length)) return SettingsStatus::FlashFailed;
    if (!flash_.program(base, head, sizeof head)) return SettingsStatus::FlashFailed;
    if (!flash_.program(base + 16, commit, sizeof commit)) return SettingsStatus::FlashFailed;
    SettingsRecord back;
    if (!check(target_sector, nullptr, 0, back) || back.seq != seq) return SettingsStatus::FlashFailed;
    if (saved) *saved = back;
    return SettingsStatus::Ok;
  }

 private:
  // a is newer than b, across the wrap of seq.
  static bool newer(uint32_t a, uint32_t b) { return int32_t(a - b) > 0; }

  // Record i's header and CRC. With buf, its payload is copied there (cap
  // bytes; a longer record does not check); without, read in chunks for
  // the CRC alone.
  bool check(int i, uint8_t* buf, size_t cap, SettingsRecord& out) const {
    const uint32_t base = flash_.sector_base(sector_[i]);
    uint8_t head[20];
    flash_.read(base, head, sizeof head);
    if (get32(head) != kMagic || get32(head + 16) != kCommit) return false;
    const uint32_t length = get32(head + 8);
    if ((buf && length > cap) || uint64_t(kHeader) + length > flash_.sector_size(sector_[i])) return false;
    Crc32 crc;
    crc.update(head + 4, 8);
    if (buf && length) {
      flash_.read(base + kHeader, buf, length);
      crc.update(buf, length);
    }
    for (uint32_t done = 0; !buf && done < length;) {
      uint8_t chunk[32];
      const uint32_t n = length - done < sizeof chunk ? length - done : uint32_t(sizeof chunk);
      flash_.read(base + kHeader + done, chunk, n);
      crc.update(chunk, n);
      done += n;
    }
    if (crc.value() != get32(head + 12)) return false;
    out = SettingsRecord{i, get32(head + 4), length};
    return true;
  }

  static void put32(uint8_t* p, uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = uint8_t(v >> (8 * i));
  }
  static uint32_t get32(const uint8_t* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
  }

  FlashPart& flash_;
  int sector_[2];
};

}  // namespace nlsoft::fw
