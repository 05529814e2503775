#include "firmware/drivers/max1111.hpp"

namespace nlsoft::fw::drivers {
namespace {

constexpr uint8_t kStart = 0x80, kSel2 = 0x40, kSel1 = 0x20, kUnipolar = 0x08, kSingleEnded = 0x04;
constexpr uint8_t kExternalClock = 0x03;  // PD1 = 1 (powered), PD0 = 1 (external clock)
constexpr float kCodes = 256.0f;

}  // namespace

uint8_t Max1111::control_byte(int channel) {
  return static_cast<uint8_t>(kStart | ((channel & 1) ? kSel2 : 0) | ((channel & 2) ? kSel1 : 0) | kUnipolar |
                              kSingleEnded | kExternalClock);
}

bool Max1111::convert(uint8_t codes[kChannels], BusStatus& status) {
  uint8_t tx[kChannels * kFrameBytes] = {};
  uint8_t rx[kChannels * kFrameBytes] = {};
  for (int ch = 0; ch < kChannels; ++ch) tx[ch * kFrameBytes] = control_byte(ch);
  status = config_.spi->transfer(config_.target, tx, rx, sizeof(tx));
  if (status != BusStatus::kOk) return false;
  for (int ch = 0; ch < kChannels; ++ch) {
    const uint8_t hi = rx[ch * kFrameBytes + 1], lo = rx[ch * kFrameBytes + 2];
    if ((hi & 0xC0) != 0 || (lo & 0x3F) != 0) return false;
    codes[ch] = static_cast<uint8_t>((hi << 2) | (lo >> 6));
  }
  return true;
}

ChipStatus Max1111::begin() {
  state_ = ChipStatus::kBadConfig;
  if (config_.spi == nullptr || !(config_.reference_volts > 0.0f)) return state_;
  uint8_t codes[kChannels];
  BusStatus status = BusStatus::kOk;
  if (convert(codes, status)) {
    state_ = ChipStatus::kOk;
  } else {
    state_ = status == BusStatus::kOk ? ChipStatus::kAbsent : ChipStatus::kBusFault;
  }
  return state_;
}

ChipStatus Max1111::read(float* out) {
  if (state_ != ChipStatus::kOk) return state_;
  uint8_t codes[kChannels];
  BusStatus status = BusStatus::kOk;
  if (!convert(codes, status)) return ChipStatus::kBusFault;
  for (int ch = 0; ch < kChannels; ++ch) out[ch] = static_cast<float>(codes[ch]) * config_.reference_volts / kCodes;
  return ChipStatus::kOk;
}

}  // namespace nlsoft::fw::drivers
