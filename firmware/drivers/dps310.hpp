#pragma once
// Infineon DPS310 pressure sensor (shared/chips/dps310.hpp) on I²C or SPI:
// pressure in Pa, temperature in °C, compensated with the chip's own
// calibration coefficients by the datasheet's formulas.
//
// begin(): PRODUCT_ID; COEF_RDY and SENSOR_RDY (a chip just powered needs
// 40 ms: begin() polls a bounded number of times, then answers kNotReady to
// be retried); the temperature retrim a mistrimmed chip needs; the nine
// coefficients; PRS_CFG/TMP_CFG (rate, oversampling,
// the temperature sensor the coefficients were made with), CFG_REG's shift
// bits above 8 times oversampling; background pressure and temperature.
// read(): the configuration still as written (a chip that reset or stopped
// driving SPI is a kBusFault, not a reading), PRS_RDY, then the six result
// bytes in one burst.
//
// QEMU's model (hw/sensor/dps310.c, 7.2) has fixed results and
// coefficients; it stores MEAS_CFG whole, ready flags included, so MEAS_CFG
// is written read-modify-write here as on the chip it does no harm: writing
// 0x07 alone would clear the model's flags for good.
#include <cstdint>

#include "firmware/drivers/chip.hpp"
#include "firmware/drivers/register_bus.hpp"
#include "shared/chips/dps310.hpp"

namespace nlsoft::fw::drivers {

class Dps310 final : public Chip {
 public:
  // Measurements averaged per result (PM_PRC / TMP_PRC): more is quieter and
  // slower (3.6 ms at 1, 206.8 ms at 128); rate × time per result for
  // pressure and temperature together must stay under a second.
  enum class Oversampling : uint8_t { k1 = 0, k2, k4, k8, k16, k32, k64, k128 };

  struct Config {
    BusAttachment bus;
    chips::Setting rate;  // one of chips::dps310::kRates (Hz), pressure and temperature alike
    Oversampling pressure_oversampling = Oversampling::k1;
    Oversampling temperature_oversampling = Oversampling::k1;
  };

  struct Coefficients {
    int32_t c0, c1, c00, c10, c01, c11, c20, c21, c30;
  };

  // Registers (datasheet v01_02).
  static constexpr uint8_t kPsrB2 = 0x00;
  static constexpr uint8_t kPrsCfg = 0x06;
  static constexpr uint8_t kMeasCfg = 0x08;
  static constexpr uint8_t kCfgReg = 0x09;
  static constexpr uint8_t kProductId = 0x0D;
  static constexpr uint8_t kCoef = 0x10;
  static constexpr uint8_t kCoefSrce = 0x28;
  static constexpr uint8_t kTrimState = 0x32, kTrimOk = 0x02;  // undocumented: the temperature trim is right
  static constexpr uint8_t kCoefRdy = 0x80, kSensorRdy = 0x40, kPrsRdy = 0x10;
  static constexpr uint8_t kBackgroundBoth = 0x07;  // MEAS_CTRL: continuous pressure and temperature
  static constexpr uint8_t kMeasCtrlMask = 0x07;
  static constexpr uint8_t kTmpExt = 0x80;          // TMP_CFG / COEF_SRCE bit 7: the MEMS element's sensor
  static constexpr uint8_t kPShift = 0x04, kTShift = 0x08;  // CFG_REG
  static constexpr int kReadyPolls = 16;
  // SPI: bit 7 reads; the address always advances on both buses.
  static constexpr RegisterConvention kConvention = {0x80, 0, 0};

  explicit Dps310(const Config& config) : config_(config), bus_(config.bus, kConvention) {}

  ChipStatus begin() override;
  ChipStatus read(float* out) override;
  int channels() const override { return 2; }

  // The 18 bytes from 0x10 as the nine signed coefficients (12, 12, 20, 20,
  // then seven 16-bit fields).
  static Coefficients decode_coefficients(const uint8_t raw[18]);
  // The datasheet's scale factor kP / kT for an oversampling.
  static float scale_factor(Oversampling o);

 private:
  Config config_;
  RegisterBus bus_;
  Coefficients coef_{};
  uint8_t cfg_[2] = {};  // PRS_CFG, TMP_CFG as written, checked on every read
  ChipStatus state_ = ChipStatus::kNotReady;  // begin()'s last answer; read() gives it until kOk
};

}  // namespace nlsoft::fw::drivers
