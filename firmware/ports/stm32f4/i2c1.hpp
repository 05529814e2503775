#pragma once
// I2C1 as a polled I²C master (RM0390 ch. 27, the F4's v1 I²C peripheral)
// on PB8 (SCL) and PB9 (SDA), the row of shared/board_stm32f4.hpp's kI2c.
// Every flag wait is bounded; a wait that runs out ends the transaction in
// kTimeout and recovers the bus (nine clocks on SCL by hand to free a chip
// holding SDA, a STOP, the peripheral reset), so the next call starts clean.
#include <cstddef>
#include <cstdint>

#include "firmware/drivers/bus.hpp"
#include "firmware/ports/stm32f4/clock_tree.hpp"

namespace nlsoft::fw::stm32f4 {

class I2c1 final : public drivers::I2cBus {
 public:
  // bus_hz: 100000 (standard mode) or 400000 (fast mode), from clocks.apb1_hz.
  I2c1(const Clocks& clocks, uint32_t bus_hz);
  // Clocks, pins and timing; again after a recovery.
  void start();
  drivers::BusStatus write_read(uint8_t addr7, const uint8_t* w, size_t wn, uint8_t* r, size_t rn) override;

  // The SCL rate the timing registers give (at or below the one asked).
  uint32_t bus_hz() const;

 private:
  drivers::BusStatus transact(uint8_t addr7, const uint8_t* w, size_t wn, uint8_t* r, size_t rn);
  drivers::BusStatus address(uint8_t byte);
  drivers::BusStatus receive(uint8_t* r, size_t rn);
  drivers::BusStatus wait_sr1(uint32_t flags);
  void recover();

  Clocks clocks_;
  uint32_t bus_hz_;
  uint32_t spins_;
};

}  // namespace nlsoft::fw::stm32f4
