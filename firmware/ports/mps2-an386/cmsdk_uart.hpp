#pragma once
// UART0 of the MPS2 board (ARM CMSDK APB UART at 0x40004000), the link to the
// console. Receive is interrupt-driven into a ring, so bytes that arrive
// during a long control step are kept (the UART holds only one); transmit is
// polled and never blocks.
#include <cstddef>
#include <cstdint>

namespace nlsoft::fw::an386 {

void uart_start(uint32_t baud);
// Bytes received so far, up to cap; 0 when none are waiting.
size_t uart_read(uint8_t* buf, size_t cap);
// Bytes the transmitter took without waiting.
size_t uart_write(const uint8_t* data, size_t len);
// True while received bytes wait in the ring, or the transmitter refused
// bytes at the last write: the loop must not sleep then.
bool uart_busy();
// Bytes lost because the ring was full (the loop did not poll in time).
uint32_t uart_rx_overruns();

}  // namespace nlsoft::fw::an386
