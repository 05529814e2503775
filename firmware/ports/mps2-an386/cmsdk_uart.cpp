#include "firmware/ports/mps2-an386/cmsdk_uart.hpp"

#include <cstddef>

#include "firmware/ports/cortex-m/board.hpp"

namespace {

struct UartRegs {
  volatile uint32_t data;
  volatile uint32_t state;      // bit 0 TX full, bit 1 RX full, bit 2/3 TX/RX overrun
  volatile uint32_t ctrl;       // bit 0 TX enable, bit 1 RX enable, bit 3 RX interrupt enable
  volatile uint32_t intstatus;  // read: pending; write 1: clear (bit 1 RX)
  volatile uint32_t bauddiv;
};
UartRegs& uart0() { return *reinterpret_cast<UartRegs*>(0x40004000u); }

constexpr uint32_t kTxFull = 1u << 0, kRxFull = 1u << 1, kRxOverrun = 1u << 3;
constexpr uint32_t kTxEnable = 1u << 0, kRxEnable = 1u << 1, kRxIntEnable = 1u << 3;
constexpr uint32_t kRxInt = 1u << 1;
constexpr uint32_t kUart0RxIrq = 0;

// Single producer (the interrupt) and single consumer (the loop): head is
// written only by the handler, tail only by the loop, so no lock is needed.
constexpr uint32_t kRing = 512;  // a power of two: indices wrap by masking
uint8_t g_ring[kRing];
volatile uint32_t g_head = 0, g_tail = 0, g_lost = 0;
bool g_tx_short = false;

volatile uint32_t& nvic_iser0() { return *reinterpret_cast<volatile uint32_t*>(0xE000E100u); }

}  // namespace

extern "C" void Uart0Rx_Handler() {
  UartRegs& u = uart0();
  // Clear first: a byte landing after the drain below raises the line again.
  u.intstatus = kRxInt;
  while (u.state & kRxFull) {
    const uint8_t b = uint8_t(u.data);
    const uint32_t h = g_head;
    if (h - g_tail < kRing) {
      g_ring[h & (kRing - 1)] = b;
      __asm volatile("" ::: "memory");  // the byte is in before the index moves
      g_head = h + 1;
    } else {
      g_lost = g_lost + 1;
    }
  }
  if (u.state & kRxOverrun) u.state = kRxOverrun;
}

namespace nlsoft::fw::an386 {

void uart_start(uint32_t clock_hz, uint32_t baud) {
  UartRegs& u = uart0();
  u.bauddiv = clock_hz / baud;
  u.ctrl = kTxEnable | kRxEnable | kRxIntEnable;
  nvic_iser0() = 1u << kUart0RxIrq;
}

uint32_t uart_rx_overruns() { return g_lost; }

}  // namespace nlsoft::fw::an386

namespace nlsoft::fw::board {

size_t serial_read(uint8_t* buf, size_t cap) {
  const uint32_t h = g_head;
  uint32_t t = g_tail;
  size_t n = 0;
  while (t != h && n < cap) buf[n++] = g_ring[t++ & (kRing - 1)];
  __asm volatile("" ::: "memory");  // bytes copied out before the slot is freed
  g_tail = t;
  return n;
}

size_t serial_write(const uint8_t* data, size_t len) {
  UartRegs& u = uart0();
  size_t n = 0;
  while (n < len && !(u.state & kTxFull)) u.data = data[n++];
  g_tx_short = n < len;
  return n;
}

bool serial_busy() { return g_head != g_tail || g_tx_short; }

}  // namespace nlsoft::fw::board
