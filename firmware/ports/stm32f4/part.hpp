#pragma once
// What differs between the Nucleo-64 parts this port builds for, selected by
// NLSOFT_STM32F4_PART_<part> from the build (option NLSOFT_STM32F4_PART):
// the top core clock, the PLL that reaches it from the 16 MHz HSI, the bus
// dividers that keep APB1/APB2 in range, flash wait states at 3.3 V, and
// whether the part needs over-drive. Values from each part's reference
// manual (RM0390 F446, RM0368 F401, RM0383 F411), clock tree chapter.
#include <cstdint>

#include "shared/board_stm32f4.hpp"

namespace nlsoft::fw::stm32f4 {

struct Part {
  const char* name;
  uint32_t core_hz;
  uint32_t pll_m, pll_n, pll_p, pll_q;  // VCO in = 16 MHz / M = 2 MHz; out = VCO / P
  uint32_t apb1_div, apb2_div;          // APB1 <= 45/42/50 MHz, APB2 <= 90/84/100 MHz
  uint32_t flash_wait_states;
  uint32_t vos;                         // PWR_CR VOS field: regulator scale for core_hz
  bool over_drive;                      // F446 above 168 MHz
};

#if defined(NLSOFT_STM32F4_PART_F446RE)
constexpr Part kPart{"f446", 180000000u, 8, 180, 2, 8, 4, 2, 5, 3, true};
#elif defined(NLSOFT_STM32F4_PART_F411RE)
constexpr Part kPart{"f411", 100000000u, 8, 100, 2, 5, 2, 1, 3, 3, false};
#elif defined(NLSOFT_STM32F4_PART_F401RE)
constexpr Part kPart{"f401", 84000000u, 8, 168, 4, 7, 2, 1, 2, 2, false};
#else
#error "define NLSOFT_STM32F4_PART_F446RE, _F411RE or _F401RE"
#endif

static_assert(kPart.core_hz / kPart.apb2_div == kServoBusClocksHz[0] || kPart.core_hz / kPart.apb2_div == kServoBusClocksHz[1] ||
                  kPart.core_hz / kPart.apb2_div == kServoBusClocksHz[2],
              "the rig loader checks servo bauds against every part's APB2 clock (shared/board_stm32f4.hpp)");
static_assert(16000000u / kPart.pll_m * kPart.pll_n / kPart.pll_p == kPart.core_hz, "PLL does not give core_hz");

// The reset clock, where a part stays when its PLL does not lock.
constexpr uint32_t kHsiHz = 16000000u;
// qemu-system-arm -M netduinoplus2 (an STM32F405) models no RCC: its
// registers read 0 and the core and SysTick run at a fixed 168 MHz.
constexpr uint32_t kEmulatedCoreHz = 168000000u;

}  // namespace nlsoft::fw::stm32f4
