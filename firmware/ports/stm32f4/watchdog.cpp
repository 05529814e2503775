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
}  // namespace

void watchdog_start() {
  reg(kDbgmcuApb1Fz) = reg(kDbgmcuApb1Fz) | kDbgIwdgStop;
  reg(kKr) = kStart;  // also starts the LSI
  reg(kKr) = kUnlock;
  reg(kPr) = kDiv32;
  reg(kRlr) = kCounts;
  // The new values cross into the LSI domain; a kick before then is lost.
  (void)wait_for([] { return reg(kSr) == 0; });
  reg(kKr) = kReload;
}

void watchdog_kick() { reg(kKr) = kReload; }

}  // namespace nlsoft::fw::stm32f4
