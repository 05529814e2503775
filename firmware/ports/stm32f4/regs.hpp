#pragma once
// The STM32F4 registers this port touches, by address (RM0390/RM0368/RM0383
// memory maps; the same on the three parts). No vendor headers: the Debian
// toolchain ships none, and the port needs a few dozen words.
#include <cstdint>

#include "firmware/ports/cortex-m/wait.hpp"
#include "shared/board_stm32f4.hpp"  // the GPIO ports (kGpioA..C), with the board's pins

namespace nlsoft::fw::stm32f4 {

inline volatile uint32_t& reg(uint32_t address) { return *reinterpret_cast<volatile uint32_t*>(address); }

namespace rcc {
constexpr uint32_t kBase = 0x40023800u;
constexpr uint32_t kCr = kBase + 0x00, kPllCfgr = kBase + 0x04, kCfgr = kBase + 0x08;
constexpr uint32_t kAhb1Enr = kBase + 0x30, kApb1Enr = kBase + 0x40, kApb2Enr = kBase + 0x44, kCsr = kBase + 0x74;
}  // namespace rcc

namespace pwr {
constexpr uint32_t kCr = 0x40007000u, kCsr = 0x40007004u;
}

constexpr uint32_t kFlashAcr = 0x40023C00u;

// A read of a clock-enable register after writing it: the enable takes
// effect before the peripheral it clocks is written (errata: two cycles).
inline void settle(uint32_t address) {
  const uint32_t v = reg(address);
  (void)v;
}

// Interrupt set-enable registers of the NVIC, 32 lines each.
inline void nvic_enable(uint32_t irq) { reg(0xE000E100u + 4 * (irq / 32)) = 1u << (irq % 32); }

using cortex_m::wait_for;  // every flag wait bounded (cortex-m/wait.hpp)

}  // namespace nlsoft::fw::stm32f4
