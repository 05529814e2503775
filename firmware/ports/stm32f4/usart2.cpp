#include "firmware/ports/stm32f4/usart2.hpp"

#include <cstddef>

#include "firmware/ports/cortex-m/board.hpp"
#include "firmware/ports/cortex-m/rx_ring.hpp"
#include "firmware/ports/stm32f4/gpio.hpp"
#include "firmware/ports/stm32f4/regs.hpp"

namespace nlsoft::fw::stm32f4 {

namespace {

constexpr uint32_t kBase = 0x40004400u;
constexpr uint32_t kSr = kBase + 0x00, kDr = kBase + 0x04, kBrr = kBase + 0x08, kCr1 = kBase + 0x0C;
constexpr uint32_t kOre = 1u << 3, kRxne = 1u << 5, kTxe = 1u << 7;
constexpr uint32_t kRe = 1u << 2, kTe = 1u << 3, kRxneIe = 1u << 5, kTxeIe = 1u << 7, kUe = 1u << 13;
constexpr uint32_t kUsart2Irq = 38;
constexpr uint32_t kUsart2En = 1u << 17;
constexpr uint32_t kAf7 = 7;

cortex_m::RxRing<512> g_rx;
// The transmit ring has one writer per index too: head in the loop, tail in
// the interrupt (or the loop with interrupts masked).
constexpr uint32_t kTxRing = 256;  // a power of two: indices wrap by masking
uint8_t g_tx[kTxRing];
volatile uint32_t g_tx_head = 0, g_tx_tail = 0;
bool g_tx_short = false;

// Hands queued bytes to the data register while it is empty. On silicon
// that is one or two bytes, the rest going out from the TXE interrupt;
// QEMU's USART sends synchronously and keeps TXE set, raising no TXE
// interrupt, so this drains the whole ring there.
void pump_tx() {
  uint32_t t = g_tx_tail;
  while (t != g_tx_head && (reg(kSr) & kTxe)) reg(kDr) = g_tx[t++ & (kTxRing - 1)];
  g_tx_tail = t;
  if (t == g_tx_head) reg(kCr1) = reg(kCr1) & ~kTxeIe;
}

}  // namespace

void usart2_start(uint32_t apb1_hz, uint32_t baud) {
  reg(rcc::kAhb1Enr) = reg(rcc::kAhb1Enr) | gpio_clock_bit(kGpioA);
  reg(rcc::kApb1Enr) = reg(rcc::kApb1Enr) | kUsart2En;
  settle(rcc::kApb1Enr);
  gpio_alternate(Pin{kGpioA, 2}, kAf7);
  gpio_alternate(Pin{kGpioA, 3}, kAf7);
  // Oversampling by 16: BRR holds fck / baud, rounded (mantissa.fraction/16).
  reg(kBrr) = (apb1_hz + baud / 2) / baud;
  reg(kCr1) = kUe | kTe | kRe | kRxneIe;
  nvic_enable(kUsart2Irq);
}

uint32_t usart2_rx_overruns() { return g_rx.lost(); }

}  // namespace nlsoft::fw::stm32f4

extern "C" void USART2_IRQHandler() {
  using namespace nlsoft::fw::stm32f4;
  // Reading SR then DR clears RXNE and an overrun alike.
  while (reg(kSr) & (kRxne | kOre)) g_rx.push(uint8_t(reg(kDr)));
  if (reg(kCr1) & kTxeIe) pump_tx();
}

namespace nlsoft::fw::board {

using namespace stm32f4;

size_t serial_read(uint8_t* buf, size_t cap) { return g_rx.read(buf, cap); }

size_t serial_write(const uint8_t* data, size_t len) {
  uint32_t h = g_tx_head;
  size_t n = 0;
  while (n < len && h - g_tx_tail < kTxRing) g_tx[h++ & (kTxRing - 1)] = data[n++];
  __asm volatile("" ::: "memory");  // the bytes are in before the index moves
  g_tx_head = h;
  // Masked: the interrupt also moves the tail and CR1.
  __asm volatile("cpsid i" ::: "memory");
  pump_tx();
  if (g_tx_tail != g_tx_head) reg(kCr1) = reg(kCr1) | kTxeIe;
  __asm volatile("cpsie i" ::: "memory");
  g_tx_short = n < len;
  return n;
}

bool serial_busy() { return !g_rx.empty() || g_tx_short; }

}  // namespace nlsoft::fw::board
