#pragma once
// What a Cortex-M board gives the shared loop (main.cpp) and HALs: its
// clocks, the link to the console and the watchdog. Each port implements
// these once (ports/mps2-an386, ports/stm32f4); the SysTick metronome and
// the reset code are common (systick.cpp, reset.cpp).
#include <cstddef>
#include <cstdint>

namespace nlsoft::fw {
class FlashPart;
}

namespace nlsoft::fw::board {

// Clock tree, tick source, link at `baud`, watchdog: everything before the
// first poll. Never hangs on a peripheral that does not answer (an emulator).
void start(uint32_t baud);
// The core clock start() reached; ticks() and the control period count in it.
uint32_t core_clock_hz();
// Free-running at core_clock_hz(), wraps at 2^32.
uint32_t ticks();

// Received bytes up to cap; 0 when none wait. Never blocks.
size_t serial_read(uint8_t* buf, size_t cap);
// Bytes the transmitter took; fewer than len when it is full. Never blocks.
size_t serial_write(const uint8_t* data, size_t len);
// True while received bytes wait, or the last write was refused in part:
// the loop must not sleep then.
bool serial_busy();

// Called once per loop turn; a loop that stops turning resets the part.
void watchdog_kick();

// The flash and the two sectors of it the settings store keeps
// (PROTOCOL.md 9.11), on a port built with NLSOFT_BOARD_SETTINGS=1; part
// null when the part's flash interface does not answer (an emulator that
// models none): the image then has no SETTINGS capability. After start().
struct SettingsFlash {
  FlashPart* part = nullptr;
  int sector_a = 0, sector_b = 0;
};
SettingsFlash settings_flash();

}  // namespace nlsoft::fw::board
