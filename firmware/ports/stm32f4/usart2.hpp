#pragma once
// USART2 on PA2 (TX) / PA3 (RX), AF7: on a Nucleo-64 the on-board ST-LINK
// bridges it to the host as a USB virtual COM port (/dev/ttyACM0), so the
// firmware needs no USB stack. The link behind board::serial_read,
// serial_write and serial_busy. Receive is interrupt-driven into a ring (the
// USART holds one byte; a control step takes longer than a byte time);
// transmit queues into a ring the TXE interrupt drains, so a write never
// waits for the line.
#include <cstdint>

namespace nlsoft::fw::stm32f4 {

void usart2_start(uint32_t apb1_hz, uint32_t baud);
// Bytes lost because the receive ring was full (the loop did not poll in time).
uint32_t usart2_rx_overruns();

}  // namespace nlsoft::fw::stm32f4
