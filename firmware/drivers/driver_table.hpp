#pragma once
// The firmware's drivers, one row each: which chips of the catalog
// (shared/chips/catalog.hpp) the driver drives, and how it is built over
// the bus a row of an image's device table (kRigDevices) attaches it to.
// An image places the rows its device table names and links no other
// (ports/cortex-m/rig_chips.hpp); a new chip's driver is its files and one
// row here.
#include <new>

#include "firmware/drivers/dps310.hpp"
#include "firmware/drivers/dynamixel_servo.hpp"
#include "firmware/drivers/lis3mdl.hpp"
#include "firmware/drivers/lsm303dlhc_mag.hpp"
#include "firmware/drivers/max1111.hpp"
#include "shared/rig_devices.hpp"

namespace nlsoft::fw::drivers {

template <class... Rows>
struct DriverTable {};

struct Lis3mdlRow {
  using Driver = Lis3mdl;
  static constexpr bool drives(const chips::ChipSpec* c) { return c == &chips::kLis3mdl; }
  static Chip* place(void* at, const RigDeviceConfig& c, const BusAttachment& bus) {
    return new (at) Lis3mdl({bus, c.range, c.rate});
  }
};

struct Lsm303dlhcMagRow {
  using Driver = Lsm303dlhcMag;
  static constexpr bool drives(const chips::ChipSpec* c) { return c == &chips::kLsm303dlhcMag; }
  static Chip* place(void* at, const RigDeviceConfig& c, const BusAttachment& bus) {
    return new (at) Lsm303dlhcMag({bus.i2c, bus.address, c.range, c.rate});
  }
};

struct Dps310Row {
  using Driver = Dps310;
  static constexpr bool drives(const chips::ChipSpec* c) { return c == &chips::kDps310; }
  static Chip* place(void* at, const RigDeviceConfig& c, const BusAttachment& bus) {
    return new (at) Dps310({bus, c.rate});
  }
};

struct Max1111Row {
  using Driver = Max1111;
  static constexpr bool drives(const chips::ChipSpec* c) { return c == &chips::kMax1111; }
  static Chip* place(void* at, const RigDeviceConfig&, const BusAttachment& bus) {
    return new (at) Max1111({bus.spi, bus.target});
  }
};

// Every servo of the catalog (Dynamixel protocol 1.0 and 2.0 alike).
struct DynamixelServoRow {
  using Driver = DynamixelServo;
  static constexpr bool drives(const chips::ChipSpec* c) { return chips::on_serial(*c); }
  static Chip* place(void* at, const RigDeviceConfig& c, const BusAttachment& bus) {
    return new (at) DynamixelServo({bus.serial, bus.address, c.chip});
  }
};

using Drivers = DriverTable<Lis3mdlRow, Lsm303dlhcMagRow, Dps310Row, Max1111Row, DynamixelServoRow>;

}  // namespace nlsoft::fw::drivers
