#pragma once
// UART0 of the MPS2 board (ARM CMSDK APB UART at 0x40004000), the link to the
// console: board::serial_read/serial_write/serial_busy. Receive is
// interrupt-driven into a ring, so bytes that arrive during a long control
// step are kept (the UART holds only one); transmit is polled and never
// blocks.
#include <cstdint>

namespace nlsoft::fw::an386 {

void uart_start(uint32_t clock_hz, uint32_t baud);
// Bytes lost because the ring was full (the loop did not poll in time).
uint32_t uart_rx_overruns();

}  // namespace nlsoft::fw::an386
