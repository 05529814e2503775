#pragma once
// An I²C master bit-banged through an ARM SBCON two-wire port (the AN386's
// I²C controllers, buses.hpp): the program drives SCL and SDA open-drain by
// writing CONTROLS (release a line: it floats high) and CONTROLC (pull it
// low), and reads both lines back from CONTROL. Timing comes from the core
// clock's tick (board::ticks), so SysTick must run (board and loop start it).
// Every wait is bounded: a chip stretching SCL past the bound, or SDA held
// low at the start and not freed by nine clocks, ends the transaction in
// kTimeout.
#include <cstddef>
#include <cstdint>

#include "firmware/drivers/bus.hpp"

namespace nlsoft::fw::an386 {

class SbconI2c final : public drivers::I2cBus {
 public:
  // base: the controller's registers; bus_hz: the SCL rate (100 or 400 kHz).
  SbconI2c(uint32_t base, uint32_t core_hz, uint32_t bus_hz);
  drivers::BusStatus write_read(uint8_t addr7, const uint8_t* w, size_t wn, uint8_t* r, size_t rn) override;

 private:
  bool idle_or_recovered();
  bool clock_high();  // releases SCL, waits while a chip stretches it
  bool send_byte(uint8_t byte, bool& acked);
  bool receive_byte(bool ack, uint8_t& byte);
  bool start();
  bool stop();
  void half_period() const;

  uint32_t base_;
  uint32_t half_ticks_;
  uint32_t stretch_spins_;
};

}  // namespace nlsoft::fw::an386
