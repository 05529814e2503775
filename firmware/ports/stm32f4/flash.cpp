// The part's flash interface behind flash.hpp, and the board's settings
// flash: sectors 1 and 2, when the interface answers.
#include "firmware/ports/stm32f4/flash.hpp"

#include "firmware/ports/cortex-m/board.hpp"
#include "firmware/ports/stm32f4/regs.hpp"
#include "firmware/ports/stm32f4/watchdog.hpp"

namespace nlsoft::fw::stm32f4 {

namespace {

struct Mmio {
  uint32_t read32(uint32_t address) { return reg(address); }
  void write32(uint32_t address, uint32_t value) { reg(address) = value; }
  void read_bytes(uint32_t address, uint8_t* out, size_t len) {
    for (size_t i = 0; i < len; ++i) out[i] = *reinterpret_cast<const volatile uint8_t*>(address + i);
  }
  // Bounds of at least four times a 16 KB erase's longest (500 ms at x32)
  // and ten times a word's (100 us), at a poll per core clock or slower.
  uint32_t erase_spins() { return cortex_m::spins_for_us(board::core_clock_hz(), 2000000u); }
  uint32_t program_spins() { return cortex_m::spins_for_us(board::core_clock_hz(), 1000u); }
  void erase_begins() { watchdog_long(true); }
  void erase_ends() { watchdog_long(false); }
};

Mmio g_mmio;

}  // namespace

}  // namespace nlsoft::fw::stm32f4

namespace nlsoft::fw::board {

SettingsFlash settings_flash() {
  using namespace stm32f4;
  // Here, not a global: an image without saved settings never calls this,
  // and then links no flash driver at all (a global would keep its vtable,
  // ~600 B of flash). constexpr: initialised in the image, no guard.
  static Flash<Mmio> part(g_mmio);
  if (!part.present()) return SettingsFlash{};
  return SettingsFlash{&part, kSettingsSectorA, kSettingsSectorB};
}

}  // namespace nlsoft::fw::board
