#include "firmware/drivers/register_bus.hpp"

namespace nlsoft::fw::drivers {

BusStatus RegisterBus::read(uint8_t reg, uint8_t* out, size_t n) {
  if (n == 0 || n > kMaxBurst) return BusStatus::kBusError;
  if (at_.i2c != nullptr) {
    const uint8_t sub = static_cast<uint8_t>(n > 1 ? reg | c_.i2c_increment : reg);
    return at_.i2c->write_read(at_.address, &sub, 1, out, n);
  }
  uint8_t tx[kMaxBurst + 1] = {};
  uint8_t rx[kMaxBurst + 1] = {};
  tx[0] = static_cast<uint8_t>(reg | c_.spi_read | (n > 1 ? c_.spi_increment : 0));
  const BusStatus s = at_.spi->transfer(at_.target, tx, rx, n + 1);
  if (s != BusStatus::kOk) return s;
  for (size_t i = 0; i < n; ++i) out[i] = rx[i + 1];
  return BusStatus::kOk;
}

BusStatus RegisterBus::write(uint8_t reg, const uint8_t* data, size_t n) {
  if (n == 0 || n > kMaxBurst) return BusStatus::kBusError;
  uint8_t tx[kMaxBurst + 1] = {};
  for (size_t i = 0; i < n; ++i) tx[i + 1] = data[i];
  if (at_.i2c != nullptr) {
    tx[0] = static_cast<uint8_t>(n > 1 ? reg | c_.i2c_increment : reg);
    return at_.i2c->write_read(at_.address, tx, n + 1, nullptr, 0);
  }
  tx[0] = static_cast<uint8_t>(n > 1 ? reg | c_.spi_increment : reg);
  return at_.spi->transfer(at_.target, tx, nullptr, n + 1);
}

ChipStatus RegisterBus::check_identity(uint8_t reg, const uint8_t* expected, size_t n) {
  uint8_t got[kMaxBurst] = {};
  const BusStatus s = read(reg, got, n);
  if (s == BusStatus::kNack) return ChipStatus::kAbsent;
  if (s != BusStatus::kOk) return ChipStatus::kBusFault;
  if (on_spi() && looks_undriven(got, n)) return ChipStatus::kAbsent;
  for (size_t i = 0; i < n; ++i)
    if (got[i] != expected[i]) return ChipStatus::kWrongId;
  return ChipStatus::kOk;
}

bool looks_undriven(const uint8_t* bytes, size_t n) {
  bool zeros = true, ones = true;
  for (size_t i = 0; i < n; ++i) {
    zeros = zeros && bytes[i] == 0x00;
    ones = ones && bytes[i] == 0xFF;
  }
  return zeros || ones;
}

}  // namespace nlsoft::fw::drivers
