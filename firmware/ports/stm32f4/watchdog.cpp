#include "firmware/ports/stm32f4/watchdog.hpp"

#include "firmware/ports/stm32f4/regs.hpp"

namespace nlsoft::fw::stm32f4 {

namespace {
constexpr uint32_t kKr = 0x40003000u, kPr = 0x40003004u, kRlr = 0x40003008u, kSr = 0x4000300Cu;
constexpr uint32_t kStart = 0xCCCCu, kUnlock = 0x5555u, kReload = 0xAAAAu;
// LSI / 32 = 1 kHz nominal; the LSI spans 17-47 kHz over parts and
// temperature, so 500 counts is 340-940 ms: far above the longest turn of
// the loop (a control step and a reply, a few ms) even at the fastest.
constexpr uint32_t kDiv32 = 3u, kCounts = 500u;
// DBGMCU_APB1_FZ.DBG_IWDG_STOP: the watchdog pauses while a debugger halts
// the core, so a breakpoint does not reset the part under the debugger.
constexpr uint32_t kDbgmcuApb1Fz = 0xE0042008u, kDbgIwdgStop = 1u << 12;

// A flash erase stalls the CPU for up to half a second (flash.hpp); LSI /
// 64 with 4095 counts is 5.6-15 s, ten times the longest 16 KB erase.
constexpr uint32_t kDiv64 = 4u, kLongCounts = 4095u;

void set_period(uint32_t prescaler, uint32_t counts) {
  // A write while the previous update still crosses into the LSI domain
  // is lost.
  (void)wait_for([] { return reg(kSr) == 0; });
  reg(kKr) = kUnlock;
  reg(kPr) = prescaler;
  reg(kRlr) = counts;
  (void)wait_for([] { return reg(kSr) == 0; });
  reg(kKr) = kReload;
}
}  // namespace

void watchdog_start() {
  reg(kDbgmcuApb1Fz) = reg(kDbgmcuApb1Fz) | kDbgIwdgStop;
  reg(kKr) = kStart;  // also starts the LSI
  set_period(kDiv32, kCounts);
}

void watchdog_long(bool on) { on ? set_period(kDiv64, kLongCounts) : set_period(kDiv32, kCounts); }

void watchdog_kick() { reg(kKr) = kReload; }

}  // namespace nlsoft::fw::stm32f4
