#include "firmware/ports/stm32f4/clock_tree.hpp"

#include "firmware/ports/stm32f4/part.hpp"
#include "firmware/ports/stm32f4/regs.hpp"

namespace nlsoft::fw::stm32f4 {

namespace {

constexpr uint32_t kHsiRdy = 1u << 1, kPllOn = 1u << 24, kPllRdy = 1u << 25;
constexpr uint32_t kPwrEn = 1u << 28;
constexpr uint32_t kOdEn = 1u << 16, kOdSwEn = 1u << 17, kOdRdy = 1u << 16, kOdSwRdy = 1u << 17;
constexpr uint32_t kFlashPrefetch = 1u << 8, kFlashICache = 1u << 9, kFlashDCache = 1u << 10;
constexpr uint32_t kSwPll = 2u, kSwsMask = 3u << 2, kSwsPll = 2u << 2;

// HPRE/PPRE encodings: 0 = /1, else 0b100 | log2(div) - 1.
constexpr uint32_t ppre(uint32_t div) { return div == 1 ? 0u : div == 2 ? 4u : div == 4 ? 5u : div == 8 ? 6u : 7u; }

Clocks on_hsi() { return Clocks{kHsiHz, kHsiHz, kHsiHz, kHsiHz, true}; }

}  // namespace

Clocks start_clock_tree() {
  // HSI is on from reset and ready within microseconds on silicon. Never
  // ready means no RCC answers: QEMU's netduinoplus2, whose clock is fixed.
  if (!wait_for([] { return (reg(rcc::kCr) & kHsiRdy) != 0; }, 10000u))
    return Clocks{kEmulatedCoreHz, kEmulatedCoreHz / kPart.apb1_div, kEmulatedCoreHz / kPart.apb2_div, kEmulatedCoreHz,
                  false};

  reg(rcc::kApb1Enr) = reg(rcc::kApb1Enr) | kPwrEn;
  settle(rcc::kApb1Enr);
  reg(pwr::kCr) = (reg(pwr::kCr) & ~(3u << 14)) | (kPart.vos << 14);

  const uint32_t p_field = kPart.pll_p / 2u - 1u;
  uint32_t cfg = kPart.pll_m | (kPart.pll_n << 6) | (p_field << 16) | (kPart.pll_q << 24);
  // Source HSI (bit 22 clear); F446's R divider (bits 28-30) keeps its reset 2.
  cfg |= reg(rcc::kPllCfgr) & (7u << 28);
  reg(rcc::kPllCfgr) = cfg;
  reg(rcc::kCr) = reg(rcc::kCr) | kPllOn;
  if (!wait_for([] { return (reg(rcc::kCr) & kPllRdy) != 0; })) return on_hsi();

  if (kPart.over_drive) {
    reg(pwr::kCr) = reg(pwr::kCr) | kOdEn;
    if (!wait_for([] { return (reg(pwr::kCsr) & kOdRdy) != 0; })) return on_hsi();
    reg(pwr::kCr) = reg(pwr::kCr) | kOdSwEn;
    if (!wait_for([] { return (reg(pwr::kCsr) & kOdSwRdy) != 0; })) return on_hsi();
  }

  // Wait states before the faster clock: flash cannot keep up otherwise.
  reg(kFlashAcr) = kPart.flash_wait_states | kFlashPrefetch | kFlashICache | kFlashDCache;
  if ((reg(kFlashAcr) & 0xFu) != kPart.flash_wait_states) return on_hsi();

  reg(rcc::kCfgr) = (ppre(kPart.apb1_div) << 10) | (ppre(kPart.apb2_div) << 13);  // AHB /1
  reg(rcc::kCfgr) = reg(rcc::kCfgr) | kSwPll;
  if (!wait_for([] { return (reg(rcc::kCfgr) & kSwsMask) == kSwsPll; })) {
    reg(rcc::kCfgr) = 0;  // back to HSI, buses undivided
    return on_hsi();
  }
  const uint32_t apb1 = kPart.core_hz / kPart.apb1_div;
  return Clocks{kPart.core_hz, apb1, kPart.core_hz / kPart.apb2_div, kPart.apb1_div == 1 ? apb1 : 2u * apb1, true};
}

}  // namespace nlsoft::fw::stm32f4
