#pragma once
// The rig's sensor chips on a Cortex-M board: one driver per row of the
// image's device table (kRigDevices in nlsoft_rig.hpp), built in place over
// the port's bus masters, and the sampler that reads them between control
// steps (firmware/core/sensor_sampler.hpp). Static storage only: a slot per
// device large enough for any driver, the driver placed in it at start().
#include <new>

#include "firmware/core/sensor_sampler.hpp"
#include "firmware/drivers/dps310.hpp"
#include "firmware/drivers/dynamixel_servo.hpp"
#include "firmware/drivers/lis3mdl.hpp"
#include "firmware/drivers/lsm303dlhc_mag.hpp"
#include "firmware/drivers/max1111.hpp"
#include "shared/rig_devices.hpp"

namespace nlsoft::fw::cortex_m {

// Count: the image's kRigDeviceCount; W: its sensor channels; Devices: its
// device table (kRigDevices), read at compile time so that the image links
// the drivers of the chips it names and no other.
template <int Count, int W, const RigDeviceConfig* Devices>
class RigChips {
  static_assert(Count <= kRigMaxDevices, "more chips than a rig file may name");
  static_assert(W <= SensorSampler::kMaxChannels, "more sensor channels than SENSOR_HEALTH's mask holds");

  static constexpr bool names(const chips::ChipSpec* chip) {
    for (int d = 0; d < Count; ++d)
      if (Devices[d].chip == chip) return true;
    return false;
  }
  static constexpr bool names_a_servo() {
    for (int d = 0; d < Count; ++d)
      if (chips::on_serial(*Devices[d].chip)) return true;
    return false;
  }
  static constexpr bool every_chip_has_a_driver() {
    for (int d = 0; d < Count; ++d) {
      const chips::ChipSpec* c = Devices[d].chip;
      if (c != &chips::kLis3mdl && c != &chips::kLsm303dlhcMag && c != &chips::kDps310 && c != &chips::kMax1111 &&
          !chips::on_serial(*c))
        return false;
    }
    return true;
  }
  static_assert(every_chip_has_a_driver(), "a chip of the device table without a driver here");

 public:
  // sources: the image's table. The port's masters by the device table's
  // bus number: I2C buses first, then SPI (the board's order, board_pins).
  explicit RigChips(const RigSensorSource* sources) : sampler_(chips_, Devices, samples_, Count, sources, W) {}

  // Builds each driver over its bus; nullptr for a bus the port lacks
  // leaves the chip absent (its begin() is never reached: kBadConfig). The
  // board's buses count I2C first, then SPI, then serial (board_pins).
  void start(drivers::I2cBus* const* i2c, int i2c_count, drivers::SpiBus* const* spi, int spi_count,
             drivers::SerialBus* const* serial = nullptr, int serial_count = 0) {
    for (int d = 0; d < Count; ++d) {
      const RigDeviceConfig& c = Devices[d];
      drivers::BusAttachment at;
      if (c.kind == BusKind::I2c) {
        at.i2c = c.bus < i2c_count ? i2c[c.bus] : nullptr;
        at.address = c.address;
      } else if (c.kind == BusKind::Serial) {
        const int k = c.bus - i2c_count - spi_count;
        at.serial = k >= 0 && k < serial_count ? serial[k] : nullptr;
        at.address = c.address;
      } else {
        const int k = c.bus - i2c_count;
        at.spi = k >= 0 && k < spi_count ? spi[k] : nullptr;
        at.target = drivers::SpiTarget{c.cs, c.chip->spi_mode, c.clock_hz};
      }
      chips_[d] = place(slots_[d], c, at);
    }
  }

  SensorSampler& sampler() { return sampler_; }
  // Device d's driver once started (a servo's, for its torque), else nullptr.
  drivers::Chip* chip(int d) const { return chips_[d]; }

 private:
  union Slot {
    Slot() {}
    ~Slot() {}
    drivers::Lis3mdl lis3mdl;
    drivers::Lsm303dlhcMag lsm303dlhc_mag;
    drivers::Dps310 dps310;
    drivers::Max1111 max1111;
    drivers::DynamixelServo servo;
  };

  // Every row's chip has a driver (every_chip_has_a_driver), so one of the
  // branches the table names always returns.
  static drivers::Chip* place(Slot& s, const RigDeviceConfig& c, const drivers::BusAttachment& at) {
    if constexpr (names(&chips::kLis3mdl))
      if (c.chip == &chips::kLis3mdl) return new (&s.lis3mdl) drivers::Lis3mdl({at, c.range, c.rate});
    if constexpr (names(&chips::kLsm303dlhcMag))
      if (c.chip == &chips::kLsm303dlhcMag)
        return new (&s.lsm303dlhc_mag) drivers::Lsm303dlhcMag({at.i2c, at.address, c.range, c.rate});
    if constexpr (names(&chips::kDps310))
      if (c.chip == &chips::kDps310) return new (&s.dps310) drivers::Dps310({at, c.rate});
    if constexpr (names(&chips::kMax1111))
      if (c.chip == &chips::kMax1111) return new (&s.max1111) drivers::Max1111({at.spi, at.target});
    if constexpr (names_a_servo())
      if (chips::on_serial(*c.chip)) return new (&s.servo) drivers::DynamixelServo({at.serial, at.address, c.chip});
    return nullptr;
  }

  Slot slots_[Count];
  drivers::Chip* chips_[Count] = {};
  SensorSampler::Slot samples_[Count];
  SensorSampler sampler_;
};

// A rig with no chip: nothing to build, and no driver, master or sampler
// linked into its image.
template <int W, const RigDeviceConfig* Devices>
class RigChips<0, W, Devices> {
 public:
  explicit RigChips(const RigSensorSource*) {}
  void start(drivers::I2cBus* const*, int, drivers::SpiBus* const*, int, drivers::SerialBus* const* = nullptr,
             int = 0) {}
};

}  // namespace nlsoft::fw::cortex_m
