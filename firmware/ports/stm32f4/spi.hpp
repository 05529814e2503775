#pragma once
// SPI1 and SPI2 as polled SPI masters (RM0390 ch. 28), pins from
// shared/board_stm32f4.hpp's kSpi, chip selects from its kChipSelect (GPIO
// outputs, high when idle, low for the whole transfer). 8-bit frames, mode
// 0..3 per target, the prescaler from the bus's APB clock: the fastest
// rate at or below the target's max_clock_hz. Every flag wait is bounded.
#include <cstddef>
#include <cstdint>

#include "firmware/drivers/bus.hpp"
#include "firmware/ports/stm32f4/clock_tree.hpp"
#include "shared/board_stm32f4.hpp"

namespace nlsoft::fw::stm32f4 {

class Spi final : public drivers::SpiBus {
 public:
  // bus: a row of kSpi.
  Spi(const SpiBusPins& bus, const Clocks& clocks);
  // Clocks, pins, and every chip select high.
  void start();
  drivers::BusStatus transfer(const drivers::SpiTarget& target, const uint8_t* tx, uint8_t* rx, size_t n) override;

  // The bit rate a chip gets: the fastest at or below its max_clock_hz.
  uint32_t bit_rate_hz(uint32_t max_clock_hz) const;

 private:
  const SpiBusPins& bus_;
  uint32_t pclk_hz_;
  uint32_t spins_;
};

}  // namespace nlsoft::fw::stm32f4
