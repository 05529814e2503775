#include "firmware/drivers/lis3mdl.hpp"

namespace nlsoft::fw::drivers {
namespace {

namespace spec = chips::lis3mdl;

// LSB per gauss at ±4, ±8, ±12, ±16 gauss (the datasheet's magnetic characteristics), in the
// order of spec::kRanges.
constexpr float kLsbPerGauss[] = {6842.0f, 3421.0f, 2281.0f, 1711.0f};
static_assert(sizeof(kLsbPerGauss) / sizeof(kLsbPerGauss[0]) == sizeof(spec::kRanges) / sizeof(spec::kRanges[0]),
              "a sensitivity per range");
constexpr float kMicroteslaPerGauss = 100.0f;

// CTRL_REG1's OM[1:0] (bits 6:5); CTRL_REG4's OMZ[1:0] is bits 3:2.
constexpr uint8_t kOmMask = 0x60;

}  // namespace

void Lis3mdl::control_registers(uint8_t out[5]) const {
  out[0] = config_.rate.bits;                                     // CTRL_REG1: OM, DO, FAST_ODR
  out[1] = config_.range.bits;                                    // CTRL_REG2: FS
  out[2] = 0x00;                                                  // CTRL_REG3: MD = continuous
  out[3] = static_cast<uint8_t>((config_.rate.bits & kOmMask) >> 3);  // CTRL_REG4: OMZ = OM
  out[4] = kBdu;                                                  // CTRL_REG5
}

ChipStatus Lis3mdl::begin() {
  state_ = ChipStatus::kBadConfig;
  const int range = chips::setting_index(spec::kRanges, chips::kLis3mdl.range_count, config_.range);
  const int rate = chips::setting_index(spec::kRates, chips::kLis3mdl.rate_count, config_.rate);
  if (!bus_.wired() || range < 0 || rate < 0) return state_;

  const uint8_t id = chips::kLis3mdl.id_value;
  state_ = bus_.check_identity(kWhoAmI, &id, 1);
  if (state_ != ChipStatus::kOk) return state_;

  uint8_t ctrl[5];
  control_registers(ctrl);
  uint8_t back[5] = {};
  state_ = ChipStatus::kBusFault;
  if (bus_.write(kCtrlReg1, ctrl, 5) != BusStatus::kOk) return state_;
  // Read back: a write the chip did not take (a broken MOSI, a chip that
  // ignores the auto-increment bit) shows here, not as wrong readings later.
  if (bus_.read(kCtrlReg1, back, 5) != BusStatus::kOk) return state_;
  for (int i = 0; i < 5; ++i)
    if (back[i] != ctrl[i]) return state_;

  ut_per_lsb_ = kMicroteslaPerGauss / kLsbPerGauss[range];
  state_ = ChipStatus::kOk;
  return state_;
}

ChipStatus Lis3mdl::read(float* out) {
  if (state_ != ChipStatus::kOk) return state_;
  // STATUS_REG (0x27) and OUT_X_L..OUT_Z_H (0x28..0x2D) are contiguous.
  uint8_t frame[7] = {};
  if (bus_.read(kStatusReg, frame, 7) != BusStatus::kOk) return ChipStatus::kBusFault;
  // A chip that stopped driving SPI's MISO reads as all ones or zeros, which
  // a live chip can also answer (an overrun at -1 LSB): WHO_AM_I decides.
  if (looks_undriven(frame, 7)) {
    const uint8_t id = chips::kLis3mdl.id_value;
    if (bus_.check_identity(kWhoAmI, &id, 1) != ChipStatus::kOk) return ChipStatus::kBusFault;
  }
  if ((frame[0] & kZyxda) == 0) return ChipStatus::kNotReady;
  for (int axis = 0; axis < 3; ++axis)
    out[axis] = static_cast<float>(le16(&frame[1 + 2 * axis])) * ut_per_lsb_;
  return ChipStatus::kOk;
}

}  // namespace nlsoft::fw::drivers
