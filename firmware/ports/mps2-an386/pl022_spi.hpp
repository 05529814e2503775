#pragma once
// A polled SPI master on an ARM PL022 (the AN386's SPI controllers,
// buses.hpp), 8-bit Motorola frames. Chip select: the PL022's own frame
// select (SSPFSSOUT), which the board routes to its connector's nCS, so a
// controller serves one chip and the only chip select is 0; any other is
// refused with kBusError. (QEMU wires no chip select to the SSI devices on
// this board: a max1111 there is always selected.) Every FIFO wait is
// bounded: a controller that never drains ends in kTimeout.
#include <cstddef>
#include <cstdint>

#include "firmware/drivers/bus.hpp"

namespace nlsoft::fw::an386 {

class Pl022Spi final : public drivers::SpiBus {
 public:
  Pl022Spi(uint32_t base, uint32_t clock_hz, uint32_t core_hz);
  drivers::BusStatus transfer(const drivers::SpiTarget& target, const uint8_t* tx, uint8_t* rx, size_t n) override;

  // The bit rate a chip gets: the fastest at or below its max_clock_hz.
  uint32_t bit_rate_hz(uint32_t max_clock_hz) const;

 private:
  uint32_t base_, clock_hz_, spins_;
};

}  // namespace nlsoft::fw::an386
