// The AN386's bus masters against QEMU's chip models (test_bus_probe_qemu.cpp
// starts it with -device lsm303dlhc_mag, dps310 and max1111 attached): on
// each request, the chips' identities, the magnetometer's X/Z/Y output
// registers, the pressure sensor's calibration coefficients, an address
// nobody answers, the other shield bus, a conversion
// of the ADC on the ADC SPI controller, and how long a 7-byte read takes on
// each bus, in core clocks.
#include "firmware/ports/cortex-m/board.hpp"
#include "firmware/ports/mps2-an386/buses.hpp"
#include "firmware/ports/mps2-an386/pl022_spi.hpp"
#include "firmware/ports/mps2-an386/sbcon_i2c.hpp"
#include "report.hpp"

namespace {

using namespace nlsoft;
using fw::an386::kI2cBuses;
using fw::an386::kSpiBuses;
using fw::drivers::BusStatus;
using fw::drivers::SpiTarget;

constexpr uint8_t kMag = 0x1E, kDps310 = 0x77, kNobody = 0x50;
constexpr uint32_t kI2cHz = 100000u;

// Leaves the magnetometer driving SDA low, as a chip does when its master
// resets mid-read: by hand on the SBCON (bit 0 SCL, bit 1 SDA; offset 0
// releases, 4 pulls low), START, its address to read, ACK, then SCL high
// on bit 7 of CRA (0x10, a 0 bit; `pointer_at_cra` put the pointer there).
// Returns the lines as they are left.
uint32_t strand_the_magnetometer(uint32_t base) {
  volatile uint32_t* set = reinterpret_cast<volatile uint32_t*>(base);
  volatile uint32_t* clear = reinterpret_cast<volatile uint32_t*>(base + 4u);
  constexpr uint32_t kScl = 1u, kSda = 2u;
  *set = kScl | kSda;
  *clear = kSda;  // START
  *clear = kScl;
  const uint8_t address = uint8_t(kMag << 1 | 1u);
  for (int bit = 7; bit >= -1; --bit) {  // -1: the acknowledge slot, SDA released
    if (bit < 0 || (address >> bit) & 1u)
      *set = kSda;
    else
      *clear = kSda;
    *set = kScl;
    *clear = kScl;
  }
  *set = kSda;
  *set = kScl;  // bit 7 of the first byte: the chip holds SDA low
  return *set;
}

void probe(test::probe::Report& out) {
  const uint32_t core = fw::board::core_clock_hz();
  fw::an386::SbconI2c shield1(kI2cBuses[1].base, core, kI2cHz);
  fw::an386::SbconI2c shield0(kI2cBuses[0].base, core, kI2cHz);

  uint8_t id[3] = {};
  const uint8_t ira = 0x0A;
  out.word("mag_id").status(shield1.write_read(kMag, &ira, 1, id, 3)).bytes(id, 3).end_line();

  // X, Z, Y (high byte first), then SR: the 7-byte read timed below.
  uint8_t xzy[7] = {};
  const uint8_t out_x_h = 0x03;
  const uint32_t t0 = fw::board::ticks();
  const BusStatus s = shield1.write_read(kMag, &out_x_h, 1, xzy, 7);
  const uint32_t i2c_ticks = fw::board::ticks() - t0;
  auto raw = [&](int at) { return int32_t(int16_t(uint16_t(xzy[at] << 8 | xzy[at + 1]))); };
  out.word("mag_xyz").status(s).number(raw(0)).number(raw(4)).number(raw(2)).end_line();
  out.word("i2c_read7_ticks").number(int32_t(i2c_ticks)).end_line();

  // QEMU's model answers PRODUCT_ID (0x0D) with 0xff (it serves only the
  // measurement, configuration and coefficient registers): the test expects
  // that, and the fixed values of what it does serve.
  uint8_t product = 0;
  const uint8_t product_id = 0x0D, meas_cfg = 0x08, coef = 0x10;
  out.word("dps310_id").status(shield1.write_read(kDps310, &product_id, 1, &product, 1)).hex(product).end_line();
  out.word("dps310_meas_cfg").status(shield1.write_read(kDps310, &meas_cfg, 1, &product, 1)).hex(product).end_line();
  uint8_t c[18] = {};
  out.word("dps310_coef").status(shield1.write_read(kDps310, &coef, 1, c, sizeof c)).bytes(c, sizeof c).end_line();

  out.word("nobody_probe").status(shield1.write_read(kNobody, nullptr, 0, nullptr, 0)).end_line();
  uint8_t junk = 0;
  out.word("nobody_read").status(shield1.write_read(kNobody, &ira, 1, &junk, 1)).end_line();
  out.word("shield0_mag").status(shield0.write_read(kMag, &ira, 1, id, 1)).end_line();

  // A bus left stuck: the next transaction clocks the chip free first.
  const uint8_t pointer_at_cra = 0x00;
  if (shield1.write_read(kMag, &pointer_at_cra, 1, nullptr, 0) == BusStatus::kOk) {
    out.word("stranded_lines").number(int32_t(strand_the_magnetometer(kI2cBuses[1].base) & 3u)).end_line();
    id[0] = id[1] = id[2] = 0;
    out.word("recovered_mag_id").status(shield1.write_read(kMag, &ira, 1, id, 3)).bytes(id, 3).end_line();
  }

  fw::an386::Pl022Spi adc_bus(kSpiBuses[2].base, fw::an386::kBusClockHz, core);
  const SpiTarget adc{0, 0, 1000000u};
  test::probe::probe_adc(adc_bus, adc, adc_bus.bit_rate_hz(adc.max_clock_hz), out);
  const uint8_t one = 0;
  uint8_t back = 0;
  out.word("spi_other_cs").status(adc_bus.transfer(SpiTarget{1, 0, 1000000u}, &one, &back, 1)).end_line();
}

}  // namespace

int main() { nlsoft::test::probe::serve(probe); }
