#pragma once
// The LSM303DLHC's magnetometer (shared/chips/lsm303dlhc_mag.hpp), I²C only:
// x, y, z in µT. begin() checks IRA/IRB/IRC ('H', '4', '3'), writes
// CRA_REG_M (rate), CRB_REG_M (gain) and MR_REG_M (continuous) one register
// per transaction and reads them back; read() takes SR_REG_M's DRDY, then
// MR_REG_M and the six output bytes, big-endian in x, z, y order from 0x03.
//
// QEMU's model (hw/sensor/lsm303dlhc_mag.c, 7.2) agrees with the datasheet
// on identity, gains, output order and read auto-increment; it differs in
// that a write transaction stores every data byte into the one register it
// addressed (hence one register per write here), DRDY is always set, and its
// mag-x/y/z properties (1 = 0.001 µT) are stored truncated to whole LSB and
// refuse every negative value ("out of register's range": the scaling goes
// through an unsigned multiply), so a QEMU test can set 0 .. +full scale only.
#include <cstdint>

#include "firmware/drivers/chip.hpp"
#include "firmware/drivers/register_bus.hpp"
#include "shared/chips/lsm303dlhc_mag.hpp"

namespace nlsoft::fw::drivers {

class Lsm303dlhcMag final : public Chip {
 public:
  struct Config {
    I2cBus* i2c = nullptr;
    uint8_t address = chips::kLsm303dlhcMag.default_address;
    chips::Setting range;  // one of chips::lsm303dlhc_mag::kRanges (gauss)
    chips::Setting rate;   // one of chips::lsm303dlhc_mag::kRates (Hz)
  };

  // Registers (datasheet DocID018771).
  static constexpr uint8_t kCraRegM = 0x00;
  static constexpr uint8_t kCrbRegM = 0x01;
  static constexpr uint8_t kMrRegM = 0x02;
  static constexpr uint8_t kOutXHM = 0x03;
  static constexpr uint8_t kContinuous = 0x00;  // MR_REG_M: MD = continuous conversion
  static constexpr uint8_t kSrRegM = 0x09;
  static constexpr uint8_t kIraRegM = 0x0A;
  static constexpr uint8_t kDrdy = 0x01;  // SR_REG_M: a new sample
  // The magnetometer's pointer always advances on a read (0x08 wraps to 0x03).
  static constexpr RegisterConvention kConvention = {0, 0, 0};

  explicit Lsm303dlhcMag(const Config& config)
      : config_(config), bus_(BusAttachment{config.i2c, config.address, nullptr, {}}, kConvention) {}

  ChipStatus begin() override;
  ChipStatus read(float* out) override;
  int channels() const override { return 3; }

 private:
  Config config_;
  RegisterBus bus_;
  float ut_per_lsb_xy_ = 0.0f;
  float ut_per_lsb_z_ = 0.0f;
  ChipStatus state_ = ChipStatus::kNotReady;  // begin()'s last answer; read() gives it until kOk
};

}  // namespace nlsoft::fw::drivers
