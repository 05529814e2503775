#include "firmware/ports/mps2-an386/cmsdk_uart.hpp"

#include <cstddef>

#include "firmware/ports/cortex-m/board.hpp"
#include "firmware/ports/cortex-m/rx_ring.hpp"

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

nlsoft::fw::cortex_m::RxRing<512> g_rx;
bool g_tx_short = false;

volatile uint32_t& nvic_iser0() { return *reinterpret_cast<volatile uint32_t*>(0xE000E100u); }

}  // namespace

extern "C" void Uart0Rx_Handler() {
  UartRegs& u = uart0();
  // Clear first: a byte landing after the drain below raises the line again.
  u.intstatus = kRxInt;
  while (u.state & kRxFull) g_rx.push(uint8_t(u.data));
  if (u.state & kRxOverrun) u.state = kRxOverrun;
}

namespace nlsoft::fw::an386 {

void uart_start(uint32_t clock_hz, uint32_t baud) {
  UartRegs& u = uart0();
  u.bauddiv = clock_hz / baud;
  u.ctrl = kTxEnable | kRxEnable | kRxIntEnable;
  nvic_iser0() = 1u << kUart0RxIrq;
}

uint32_t uart_rx_overruns() { return g_rx.lost(); }

}  // namespace nlsoft::fw::an386

namespace nlsoft::fw::board {

size_t serial_read(uint8_t* buf, size_t cap) { return g_rx.read(buf, cap); }

size_t serial_write(const uint8_t* data, size_t len) {
  UartRegs& u = uart0();
  size_t n = 0;
  while (n < len && !(u.state & kTxFull)) u.data = data[n++];
  g_tx_short = n < len;
  return n;
}

bool serial_busy() { return !g_rx.empty() || g_tx_short; }

}  // namespace nlsoft::fw::board
