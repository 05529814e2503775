#pragma once
// The independent watchdog (IWDG), clocked by the ~32 kHz LSI: a loop that
// stops turning (a fault handler's trap, a wedged peripheral wait) resets
// the part within about half a second, and the console sees the board come
// back instead of a silent heartbeat. Once started it cannot be stopped.
namespace nlsoft::fw::stm32f4 {

void watchdog_start();
void watchdog_kick();
// on: a period of tens of seconds, for a flash erase that stalls the CPU;
// off: back to the half second.
void watchdog_long(bool on);

}  // namespace nlsoft::fw::stm32f4
