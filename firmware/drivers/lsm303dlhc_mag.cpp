#include "firmware/drivers/lsm303dlhc_mag.hpp"

namespace nlsoft::fw::drivers {
namespace {

namespace spec = chips::lsm303dlhc_mag;

// LSB per gauss per gain (datasheet table 3), in the order of
// spec::kRanges: x and y share one figure, z has its own.
constexpr float kXyLsbPerGauss[] = {1100.0f, 855.0f, 670.0f, 450.0f, 400.0f, 330.0f, 230.0f};
constexpr float kZLsbPerGauss[] = {980.0f, 760.0f, 600.0f, 400.0f, 355.0f, 295.0f, 205.0f};
constexpr int kRanges = sizeof(spec::kRanges) / sizeof(spec::kRanges[0]);
static_assert(sizeof(kXyLsbPerGauss) / sizeof(float) == kRanges && sizeof(kZLsbPerGauss) / sizeof(float) == kRanges,
              "a sensitivity per gain");
constexpr float kMicroteslaPerGauss = 100.0f;
constexpr uint8_t kIdentity[] = {'H', '4', '3'};  // IRA_REG_M, IRB_REG_M, IRC_REG_M

}  // namespace

ChipStatus Lsm303dlhcMag::begin() {
  state_ = ChipStatus::kBadConfig;
  const int range = chips::setting_index(spec::kRanges, chips::kLsm303dlhcMag.range_count, config_.range);
  const int rate = chips::setting_index(spec::kRates, chips::kLsm303dlhcMag.rate_count, config_.rate);
  if (!bus_.wired() || range < 0 || rate < 0) return state_;

  state_ = bus_.check_identity(kIraRegM, kIdentity, sizeof(kIdentity));
  if (state_ != ChipStatus::kOk) return state_;

  // CRA: rate, temperature sensor off; CRB: gain; MR: continuous conversion.
  const uint8_t want[3] = {config_.rate.bits, config_.range.bits, kContinuous};
  state_ = ChipStatus::kBusFault;
  for (uint8_t i = 0; i < 3; ++i)
    if (bus_.write(static_cast<uint8_t>(kCraRegM + i), want[i]) != BusStatus::kOk) return state_;
  uint8_t back[3] = {};
  if (bus_.read(kCraRegM, back, 3) != BusStatus::kOk) return state_;
  for (int i = 0; i < 3; ++i)
    if (back[i] != want[i]) return state_;

  ut_per_lsb_xy_ = kMicroteslaPerGauss / kXyLsbPerGauss[range];
  ut_per_lsb_z_ = kMicroteslaPerGauss / kZLsbPerGauss[range];
  state_ = ChipStatus::kOk;
  return state_;
}

ChipStatus Lsm303dlhcMag::read(float* out) {
  if (state_ != ChipStatus::kOk) return state_;
  uint8_t sr = 0;
  if (bus_.read(kSrRegM, &sr, 1) != BusStatus::kOk) return ChipStatus::kBusFault;
  if ((sr & kDrdy) == 0) return ChipStatus::kNotReady;
  // MR_REG_M tells a chip that reset itself (back to sleep, its last sample
  // frozen) from one still converting. The outputs are a burst of their own
  // from OUT_X_H: QEMU's model takes a new sample only for a read that
  // starts there (a burst from MR_REG_M got the first sample for ever).
  uint8_t mr = 0;
  if (bus_.read(kMrRegM, &mr, 1) != BusStatus::kOk || mr != kContinuous) return ChipStatus::kBusFault;
  uint8_t frame[6] = {};  // X_H X_L Z_H Z_L Y_H Y_L
  if (bus_.read(kOutXHM, frame, 6) != BusStatus::kOk) return ChipStatus::kBusFault;
  out[0] = static_cast<float>(be16(&frame[0])) * ut_per_lsb_xy_;
  out[1] = static_cast<float>(be16(&frame[4])) * ut_per_lsb_xy_;
  out[2] = static_cast<float>(be16(&frame[2])) * ut_per_lsb_z_;
  return ChipStatus::kOk;
}

}  // namespace nlsoft::fw::drivers
