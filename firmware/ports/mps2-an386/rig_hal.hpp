#pragma once
// The real-board build: the link and the clock as on the HIL image; no
// actuators and no ADC (the AN386 has nothing to drive); the rig's sensor
// chips ([[device]]) on the board's shield I2C and SPI buses (buses.hpp),
// sampled between control steps (rig_chips.hpp). A sensor channel of an
// ADC reads 0 here; one of a chip reads the chip. The image's size is the
// footprint we report for controller + protocol.
#include <new>
#include <type_traits>

#include "firmware/core/hal.hpp"
#include "firmware/ports/cortex-m/board.hpp"
#include "firmware/ports/cortex-m/platform_config.hpp"
#include "firmware/ports/cortex-m/rig_chips.hpp"
#include "firmware/ports/mps2-an386/buses.hpp"
#include "firmware/ports/mps2-an386/pl022_spi.hpp"
#include "firmware/ports/mps2-an386/sbcon_i2c.hpp"

namespace nlsoft::fw::cortex_m {

template <int M, int W>
class RigHal final : public Hal {
  static constexpr int kI2c = int(sizeof an386::kI2cBuses / sizeof an386::kI2cBuses[0]);
  static constexpr int kSpi = int(sizeof an386::kSpiBuses / sizeof an386::kSpiBuses[0]);

 public:
  static constexpr bool kMeasuresOutput = false;
  size_t serial_read(uint8_t* buf, size_t cap) override { return board::serial_read(buf, cap); }
  size_t serial_write(const uint8_t* data, size_t len) override { return board::serial_write(data, len); }
  uint32_t ticks() override { return board::ticks(); }
  uint32_t tick_rate_hz() const override { return board::core_clock_hz(); }
  void actuate(const float*, int) override {}
  void read_sensors(float* l, int w) override {
    for (int i = 0; i < w; ++i) l[i] = 0.0f;  // the chips' channels are written over by the sampler
  }
  bool read_output(float*, int) override { return false; }  // no observer of y on a plain board

  void start() {
    if constexpr (kRigDeviceCount > 0) start_chips(buses_);
  }
  void advance() {}
  // The sampler the firmware reads the chips through (an image with chips).
  SensorSampler& sensors() { return chips_.sampler(); }

 private:
  // The masters, each I2C bus at the slowest clock its chips take, then the drivers.
  template <class Buses>
  void start_chips(Buses& buses) {
    const uint32_t core = board::core_clock_hz();
    drivers::I2cBus* i2c[kI2c];
    drivers::SpiBus* spi[kSpi];
    for (int b = 0; b < kI2c; ++b) i2c[b] = new (&buses.i2c[b]) an386::SbconI2c(an386::kI2cBuses[b].base, core, i2c_hz(b));
    for (int b = 0; b < kSpi; ++b)
      spi[b] = new (&buses.spi[b]) an386::Pl022Spi(an386::kSpiBuses[b].base, an386::kBusClockHz, core);
    chips_.start(i2c, kI2c, spi, kSpi);
  }

  static uint32_t i2c_hz(int bus) {
    uint32_t hz = 400000u;
    for (int d = 0; d < kRigDeviceCount; ++d)
      if (kRigDevices[d].kind == BusKind::I2c && kRigDevices[d].bus == bus && kRigDevices[d].clock_hz < hz)
        hz = kRigDevices[d].clock_hz;
    return hz;
  }

  // Raw storage: the masters need the core clock, known only once the board started.
  union I2cSlot {
    I2cSlot() {}
    ~I2cSlot() {}
    an386::SbconI2c bus;
  };
  union SpiSlot {
    SpiSlot() {}
    ~SpiSlot() {}
    an386::Pl022Spi bus;
  };
  struct Buses {
    I2cSlot i2c[kI2c];
    SpiSlot spi[kSpi];
  };
  struct NoBuses {};
  // Room for the masters in an image with chips only.
  [[no_unique_address]] std::conditional_t<(kRigDeviceCount > 0), Buses, NoBuses> buses_;
  RigChips<kRigDeviceCount, W, kRigDevices> chips_{kRigSensorSources};
};

}  // namespace nlsoft::fw::cortex_m
