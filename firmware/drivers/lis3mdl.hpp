#pragma once
// ST LIS3MDL magnetometer (shared/chips/lis3mdl.hpp) on SPI or I²C: x, y, z
// in µT. begin() checks WHO_AM_I, writes CTRL_REG1..5 in one burst (rate,
// range, continuous conversion, z in x and y's operating mode, block data
// update) and reads them back; read() takes STATUS_REG and the six output
// bytes in one burst, so a step costs one transaction.
#include <cstdint>

#include "firmware/drivers/chip.hpp"
#include "firmware/drivers/register_bus.hpp"
#include "shared/chips/lis3mdl.hpp"

namespace nlsoft::fw::drivers {

class Lis3mdl final : public Chip {
 public:
  struct Config {
    BusAttachment bus;
    chips::Setting range;  // one of chips::lis3mdl::kRanges (gauss)
    chips::Setting rate;   // one of chips::lis3mdl::kRates (Hz)
  };

  // Registers (datasheet DocID024204).
  static constexpr uint8_t kWhoAmI = 0x0F;
  static constexpr uint8_t kCtrlReg1 = 0x20;
  static constexpr uint8_t kStatusReg = 0x27;
  static constexpr uint8_t kOutXL = 0x28;
  static constexpr uint8_t kZyxda = 0x08;  // STATUS_REG: a new x, y, z sample
  static constexpr uint8_t kBdu = 0x40;    // CTRL_REG5: outputs not updated between a sample's two bytes
  // SPI: bit 7 reads, bit 6 auto-increments; I²C: bit 7 auto-increments.
  static constexpr RegisterConvention kConvention = {0x80, 0x40, 0x80};

  explicit Lis3mdl(const Config& config) : config_(config), bus_(config.bus, kConvention) {}

  ChipStatus begin() override;
  ChipStatus read(float* out) override;
  int channels() const override { return 3; }

 private:
  // The CTRL_REG1..5 values begin() writes for this configuration.
  void control_registers(uint8_t out[5]) const;

  Config config_;
  RegisterBus bus_;
  float ut_per_lsb_ = 0.0f;
  ChipStatus state_ = ChipStatus::kNotReady;  // begin()'s last answer; read() gives it until kOk
};

}  // namespace nlsoft::fw::drivers
