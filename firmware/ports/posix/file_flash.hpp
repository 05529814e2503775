#pragma once
// The simulator's settings flash: two 16 KiB sectors in a file, with a NOR
// part's rules (erase sets a sector to 0xFF, programming only clears bits),
// so the settings store behaves on the host as on a board and its records
// survive a restart of the simulator.
#include <cstddef>
#include <cstdint>
#include <string>

#include "firmware/core/settings_store.hpp"

namespace nlsoft::fw::posix {

class FileFlash final : public FlashPart {
 public:
  static constexpr uint32_t kSectorSize = 16384;
  static constexpr int kSectors = 2;

  FileFlash() = default;
  ~FileFlash();
  FileFlash(const FileFlash&) = delete;
  FileFlash& operator=(const FileFlash&) = delete;

  enum class Opened { Ok, Busy, Failed };
  // Opens the file, creating it erased (all 0xFF) when it does not exist.
  // Busy: another simulator holds it (one board per flash chip). Busy and
  // Failed say why in `error`.
  Opened open(const std::string& path, std::string& error);

  uint32_t sector_base(int sector) const override { return uint32_t(sector) * kSectorSize; }
  uint32_t sector_size(int) const override { return kSectorSize; }
  bool erase(int sector) override;
  bool program(uint32_t addr, const uint8_t* data, size_t len) override;
  void read(uint32_t addr, uint8_t* out, size_t len) const override;

 private:
  int fd_ = -1;
};

}  // namespace nlsoft::fw::posix
