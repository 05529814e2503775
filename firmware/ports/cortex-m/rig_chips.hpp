#pragma once
// The rig's sensor chips on a Cortex-M board: one driver per row of the
// image's device table (kRigDevices in nlsoft_rig.hpp), built in place over
// the port's bus masters, and the sampler that reads them between control
// steps (firmware/core/sensor_sampler.hpp). Static storage only: a slot per
// device large enough for any driver, the driver placed in it at start().
#include <cstddef>
#include <initializer_list>

#include "firmware/core/sensor_sampler.hpp"
#include "firmware/drivers/driver_table.hpp"
#include "shared/rig_devices.hpp"

namespace nlsoft::fw::cortex_m {

// A device table (Count rows at Devices) against the driver table: whether
// every row's chip has a driver, a slot that holds any driver the table
// names, and the placing of row d's driver, instantiated only for the rows'
// drivers so that an image links those and no other.
template <int Count, const RigDeviceConfig* Devices, class Table>
struct DeviceDrivers;

template <int Count, const RigDeviceConfig* Devices, class... Rows>
struct DeviceDrivers<Count, Devices, drivers::DriverTable<Rows...>> {
  template <class Row>
  static constexpr bool named() {
    for (int d = 0; d < Count; ++d)
      if (Row::drives(Devices[d].chip)) return true;
    return false;
  }
  static constexpr bool every_chip_has_a_driver() {
    for (int d = 0; d < Count; ++d)
      if (!(Rows::drives(Devices[d].chip) || ...)) return false;
    return true;
  }
  static constexpr size_t max_of(std::initializer_list<size_t> v) {
    size_t m = 1;
    for (size_t x : v) m = x > m ? x : m;
    return m;
  }
  struct Slot {
    alignas(max_of({alignof(typename Rows::Driver)...})) unsigned char bytes[max_of({sizeof(typename Rows::Driver)...})];
  };
  template <class Row>
  static drivers::Chip* try_place(Slot& s, const RigDeviceConfig& c, const drivers::BusAttachment& at) {
    if constexpr (named<Row>())
      if (Row::drives(c.chip)) return Row::place(s.bytes, c, at);
    return nullptr;
  }
  static drivers::Chip* place(Slot& s, const RigDeviceConfig& c, const drivers::BusAttachment& at) {
    drivers::Chip* chip = nullptr;
    ((chip = chip != nullptr ? chip : try_place<Rows>(s, c, at)), ...);
    return chip;
  }
};

// Count: the image's kRigDeviceCount; W: its sensor channels; Devices: its
// device table (kRigDevices), read at compile time so that the image links
// the drivers of the chips it names and no other.
template <int Count, int W, const RigDeviceConfig* Devices>
class RigChips {
  static_assert(Count <= kRigMaxDevices, "more chips than a rig file may name");
  static_assert(W <= SensorSampler::kMaxChannels, "more sensor channels than SENSOR_HEALTH's mask holds");

  using Table = DeviceDrivers<Count, Devices, drivers::Drivers>;
  static_assert(Table::every_chip_has_a_driver(), "a chip of the device table without a driver (drivers/driver_table.hpp)");

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
      chips_[d] = Table::place(slots_[d], c, at);
    }
  }

  SensorSampler& sampler() { return sampler_; }
  // Device d's driver once started (a servo's, for its torque), else nullptr.
  drivers::Chip* chip(int d) const { return chips_[d]; }

 private:
  using Slot = typename Table::Slot;
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
