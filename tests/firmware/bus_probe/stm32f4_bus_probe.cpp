// The stm32f4 port's bus masters in QEMU's netduinoplus2 (an STM32F405,
// test_bus_probe_qemu.cpp): its SPI controllers are modelled (polled, no
// RCC) and a `-device max1111` with no bus= lands on the last one QEMU
// creates, at 0x40015400 (an SPI6 the F405 itself does not have), so the
// probe drives that controller with the same master as SPI1/SPI2: a
// conversion of the ADC, then SPI1 and SPI2 with nothing attached. I2C1 is
// not modelled (its registers read 0): the master must give up with
// kTimeout, not hang.
#include <initializer_list>

#include "firmware/ports/cortex-m/board.hpp"
#include "firmware/ports/stm32f4/clock_tree.hpp"
#include "firmware/ports/stm32f4/i2c1.hpp"
#include "firmware/ports/stm32f4/spi.hpp"
#include "report.hpp"

namespace {

using namespace nlsoft;
using fw::drivers::BusStatus;
using fw::drivers::SpiTarget;
namespace f4 = fw::stm32f4;

// QEMU's extra controller: SPI1's register layout and, here, its pins.
constexpr f4::SpiBusPins kQemuSpi{"qemu-spi", 0x40015400u, f4::kSpi[0].sck, f4::kSpi[0].miso, f4::kSpi[0].mosi,
                                  true};

void probe(test::probe::Report& out) {
  const f4::Clocks& clocks = f4::board_clocks();
  f4::Spi adc_bus(kQemuSpi, clocks);
  adc_bus.start();
  const SpiTarget adc{2, 0, 1000000u};
  test::probe::probe_adc(adc_bus, adc, adc_bus.bit_rate_hz(adc.max_clock_hz), out);
  const uint8_t seven[7] = {0x8F, 0, 0, 0, 0, 0, 0};
  uint8_t back[7] = {};
  for (const f4::SpiBusPins& bus : f4::kSpi) {
    f4::Spi empty(bus, clocks);
    empty.start();
    uint8_t rx[2] = {0xAA, 0xAA};
    out.word(bus.name).status(empty.transfer(SpiTarget{0, 3, 10000000u}, seven, rx, 2)).bytes(rx, 2)
        .number(int32_t(empty.bit_rate_hz(10000000u))).end_line();
  }
  out.word("spi_bad_cs").status(adc_bus.transfer(SpiTarget{uint8_t(f4::kChipSelectCount), 0, 1000000u}, seven, back, 1))
      .end_line();

  f4::I2c1 i2c(clocks, 400000u);
  i2c.start();
  uint8_t id = 0;
  const uint8_t reg = 0x0F;
  const uint32_t t1 = fw::board::ticks();
  const BusStatus st = i2c.write_read(0x1E, &reg, 1, &id, 1);
  out.word("i2c1").status(st).number(int32_t(i2c.bus_hz())).end_line();
  out.word("i2c1_gave_up_ticks").number(int32_t(fw::board::ticks() - t1)).end_line();
}

}  // namespace

int main() { nlsoft::test::probe::serve(probe); }
