#include "firmware/drivers/dps310.hpp"

namespace nlsoft::fw::drivers {
namespace {

// Two's complement of the low `bits` bits of v.
int32_t sign_extend(uint32_t v, int bits) {
  const uint32_t sign = 1u << (bits - 1);
  return static_cast<int32_t>(v ^ sign) - static_cast<int32_t>(sign);
}

uint8_t prc_bits(Dps310::Oversampling o) { return static_cast<uint8_t>(o); }
bool needs_shift(Dps310::Oversampling o) { return o > Dps310::Oversampling::k8; }

}  // namespace

Dps310::Coefficients Dps310::decode_coefficients(const uint8_t b[18]) {
  Coefficients c{};
  c.c0 = sign_extend((uint32_t{b[0]} << 4) | (b[1] >> 4), 12);
  c.c1 = sign_extend((uint32_t{b[1]} & 0x0F) << 8 | b[2], 12);
  c.c00 = sign_extend((uint32_t{b[3]} << 12) | (uint32_t{b[4]} << 4) | (b[5] >> 4), 20);
  c.c10 = sign_extend((uint32_t{b[5]} & 0x0F) << 16 | (uint32_t{b[6]} << 8) | b[7], 20);
  int32_t* sixteen[] = {&c.c01, &c.c11, &c.c20, &c.c21, &c.c30};
  for (int i = 0; i < 5; ++i) *sixteen[i] = sign_extend((uint32_t{b[8 + 2 * i]} << 8) | b[9 + 2 * i], 16);
  return c;
}

float Dps310::scale_factor(Oversampling o) {
  // The datasheet's compensation scale factors, in the order of Oversampling.
  static constexpr float kScale[] = {524288.0f, 1572864.0f, 3670016.0f, 7864320.0f,
                                     253952.0f, 516096.0f,  1040384.0f, 2088960.0f};
  return kScale[static_cast<int>(o) & 7];
}

ChipStatus Dps310::begin() {
  state_ = ChipStatus::kBadConfig;
  if (!bus_.wired() || chips::setting_index(chips::dps310::kRates, chips::kDps310.rate_count, config_.rate) < 0 ||
      config_.pressure_oversampling > Oversampling::k128 || config_.temperature_oversampling > Oversampling::k128)
    return state_;

  const uint8_t id = chips::kDps310.id_value;
  state_ = bus_.check_identity(kProductId, &id, 1);
  if (state_ != ChipStatus::kOk) return state_;

  uint8_t meas = 0;
  state_ = ChipStatus::kNotReady;
  for (int i = 0; i < kReadyPolls && (meas & (kCoefRdy | kSensorRdy)) != (kCoefRdy | kSensorRdy); ++i)
    if (bus_.read(kMeasCfg, &meas, 1) != BusStatus::kOk) return state_ = ChipStatus::kBusFault;
  if ((meas & (kCoefRdy | kSensorRdy)) != (kCoefRdy | kSensorRdy)) return state_;

  state_ = ChipStatus::kBusFault;
  // Some DPS310s left the factory with their temperature path mistrimmed
  // (readings tens of degrees off); register 0x32 bit 1 says a chip is
  // fine, else a fixed write sequence retrims it (Infineon's reference
  // driver and Linux's apply the same; QEMU's model reads 0x32 = 0x02).
  uint8_t trim = 0;
  if (bus_.read(kTrimState, &trim, 1) != BusStatus::kOk) return state_;
  if ((trim & kTrimOk) == 0) {
    static constexpr uint8_t kRetrim[][2] = {{0x0E, 0xA5}, {0x0F, 0x96}, {0x62, 0x02}, {0x0E, 0x00}, {0x0F, 0x00}};
    for (const auto& w : kRetrim)
      if (bus_.write(w[0], w[1]) != BusStatus::kOk) return state_;
  }
  uint8_t raw[18] = {};
  uint8_t srce = 0;
  if (bus_.read(kCoef, raw, 18) != BusStatus::kOk || bus_.read(kCoefSrce, &srce, 1) != BusStatus::kOk) return state_;
  coef_ = decode_coefficients(raw);

  // The temperature must come from the sensor the coefficients were
  // calibrated against (COEF_SRCE), or it reads wrong by degrees.
  cfg_[0] = static_cast<uint8_t>(config_.rate.bits | prc_bits(config_.pressure_oversampling));
  cfg_[1] = static_cast<uint8_t>((srce & kTmpExt) | config_.rate.bits | prc_bits(config_.temperature_oversampling));
  const uint8_t shift = static_cast<uint8_t>((needs_shift(config_.pressure_oversampling) ? kPShift : 0) |
                                             (needs_shift(config_.temperature_oversampling) ? kTShift : 0));
  // Configuration first, measurement last: the chip starts measuring with
  // whatever the other registers hold when MEAS_CTRL is written.
  const uint8_t start = static_cast<uint8_t>((meas & ~kMeasCtrlMask) | kBackgroundBoth);
  if (bus_.write(kCfgReg, shift) != BusStatus::kOk || bus_.write(kPrsCfg, cfg_, 2) != BusStatus::kOk ||
      bus_.write(kMeasCfg, start) != BusStatus::kOk)
    return state_;
  uint8_t back[4] = {};  // PRS_CFG, TMP_CFG, MEAS_CFG, CFG_REG
  if (bus_.read(kPrsCfg, back, 4) != BusStatus::kOk) return state_;
  if (back[0] != cfg_[0] || back[1] != cfg_[1] || (back[2] & kMeasCtrlMask) != kBackgroundBoth || back[3] != shift)
    return state_;

  state_ = ChipStatus::kOk;
  return state_;
}

ChipStatus Dps310::read(float* out) {
  if (state_ != ChipStatus::kOk) return state_;
  uint8_t cfg[3] = {};  // PRS_CFG, TMP_CFG, MEAS_CFG
  if (bus_.read(kPrsCfg, cfg, 3) != BusStatus::kOk) return ChipStatus::kBusFault;
  if (cfg[0] != cfg_[0] || cfg[1] != cfg_[1] || (cfg[2] & kMeasCtrlMask) != kBackgroundBoth)
    return ChipStatus::kBusFault;
  if ((cfg[2] & kPrsRdy) == 0) return ChipStatus::kNotReady;
  uint8_t r[6] = {};
  if (bus_.read(kPsrB2, r, 6) != BusStatus::kOk) return ChipStatus::kBusFault;

  const int32_t p_raw = sign_extend((uint32_t{r[0]} << 16) | (uint32_t{r[1]} << 8) | r[2], 24);
  const int32_t t_raw = sign_extend((uint32_t{r[3]} << 16) | (uint32_t{r[4]} << 8) | r[5], 24);
  const float p = static_cast<float>(p_raw) / scale_factor(config_.pressure_oversampling);
  const float t = static_cast<float>(t_raw) / scale_factor(config_.temperature_oversampling);
  const Coefficients& c = coef_;
  auto f = [](int32_t v) { return static_cast<float>(v); };
  out[0] = f(c.c00) + p * (f(c.c10) + p * (f(c.c20) + p * f(c.c30))) + t * f(c.c01) +
           t * p * (f(c.c11) + p * f(c.c21));
  out[1] = f(c.c0) * 0.5f + f(c.c1) * t;
  return ChipStatus::kOk;
}

}  // namespace nlsoft::fw::drivers
