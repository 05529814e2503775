#pragma once
// A servo bus: USART1 or USART6 in single-wire half-duplex mode (RM0390
// 25.3.10, HDSEL) on its TX pin, open-drain with the pull-up, as the
// Dynamixel line is wired (a TTL chain straight to the pin; an RS-485
// chain through a transceiver). Polled, every wait bounded by the core
// clock: the port's vector table is unchanged and an image without servos
// links none of this.
//
// The receiver is off while the USART transmits, so the line's echo of our
// own bytes never arrives. exchange() then listens until the caller's
// `cap` bytes came (a 1.0 answer's length is known), or for at most
// kAnswerUs for the first byte (a servo's return delay, 500 us at an
// RX-64's factory setting, and a margin) and kGapUs between bytes. Under
// an emulator (no RCC answers: QEMU's netduinoplus2) the servo is a
// program on a pty whose answer crosses the host's scheduler, milliseconds
// on a loaded machine, so the waits are kEmulatedAnswerUs and
// kEmulatedGapUs there: a silent servo then costs the loop that long at
// each retry (once a second).
// send() returns once its last byte is in the data register: a 2-servo
// 1.0 SYNC_WRITE is 14 bytes, 140 us at 1 Mbit/s (of tendon's 8.3 ms
// period), waited for byte by byte; a TX interrupt or DMA would give that
// time back to the loop at the cost of a vector in every image.
#include <cstddef>
#include <cstdint>

#include "firmware/drivers/bus.hpp"
#include "firmware/ports/stm32f4/clock_tree.hpp"
#include "shared/board_stm32f4.hpp"

namespace nlsoft::fw::stm32f4 {

class ServoUsart final : public drivers::SerialBus {
 public:
  static constexpr uint32_t kAnswerUs = 4000, kGapUs = 300;
  static constexpr uint32_t kEmulatedAnswerUs = 30000, kEmulatedGapUs = 10000;

  // bus: a row of kServoBus.
  ServoUsart(const SerialBusPins& bus, const Clocks& clocks, uint32_t baud);
  void start();
  drivers::BusStatus exchange(const uint8_t* tx, size_t n, uint8_t* rx, size_t cap, size_t& got) override;
  drivers::BusStatus send(const uint8_t* tx, size_t n) override;

 private:
  bool transmit(const uint8_t* tx, size_t n, bool until_sent);
  uint32_t base() const { return bus_.base; }

  const SerialBusPins& bus_;
  uint32_t pclk_hz_, baud_, core_hz_;
  uint32_t answer_us_, gap_us_;
  uint32_t byte_spins_;  // polls a byte may take: two byte times and 20 us
};

}  // namespace nlsoft::fw::stm32f4
