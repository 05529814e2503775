#pragma once
// A chip's registers over whichever bus it is wired to. The chips differ in
// how a transaction names a register: SPI's read bit and auto-increment bit,
// I²C's auto-increment bit (LIS3MDL) or none (chips that always increment).
// The drivers say which in a RegisterConvention and read and write bursts.
#include <cstddef>
#include <cstdint>

#include "firmware/drivers/bus.hpp"
#include "firmware/drivers/chip.hpp"

namespace nlsoft::fw::drivers {

// Where a chip is wired: exactly one of i2c (at address) or spi (at target).
struct BusAttachment {
  I2cBus* i2c = nullptr;
  uint8_t address = 0;
  SpiBus* spi = nullptr;
  SpiTarget target{};
  SerialBus* serial = nullptr;  // a servo's bus; `address` is then its id
};

struct RegisterConvention {
  uint8_t spi_read;       // OR-ed into the register byte of a SPI read
  uint8_t spi_increment;  // ... of a SPI burst (read or write) of more than one byte
  uint8_t i2c_increment;  // ... of an I²C burst of more than one byte
};

class RegisterBus {
 public:
  // The longest burst: the DPS310's 18 calibration bytes, with room.
  static constexpr size_t kMaxBurst = 24;

  RegisterBus(const BusAttachment& at, RegisterConvention c) : at_(at), c_(c) {}

  // Exactly one bus named.
  bool wired() const { return (at_.i2c != nullptr) != (at_.spi != nullptr); }
  bool on_spi() const { return at_.spi != nullptr; }

  // n bytes from `reg` on; kBusError for a burst longer than kMaxBurst.
  BusStatus read(uint8_t reg, uint8_t* out, size_t n);
  BusStatus write(uint8_t reg, const uint8_t* data, size_t n);
  BusStatus write(uint8_t reg, uint8_t value) { return write(reg, &value, 1); }

  // The identity check every driver's begin() makes: `n` bytes from `reg`
  // against `expected`. kAbsent when nothing answered (an I²C NACK; on SPI
  // every byte 0x00 or every byte 0xFF, what a floating or pulled line
  // reads), kWrongId when something else did, kBusFault when the bus failed.
  ChipStatus check_identity(uint8_t reg, const uint8_t* expected, size_t n);

 private:
  BusAttachment at_;
  RegisterConvention c_;
};

// What a register frame of n bytes looks like from a chip that is not
// driving the line: every byte 0x00 or every byte 0xFF.
bool looks_undriven(const uint8_t* bytes, size_t n);

// A little- or big-endian two's complement 16-bit value.
inline int16_t le16(const uint8_t* p) { return static_cast<int16_t>(static_cast<uint16_t>(p[0] | (p[1] << 8))); }
inline int16_t be16(const uint8_t* p) { return static_cast<int16_t>(static_cast<uint16_t>((p[0] << 8) | p[1])); }

}  // namespace nlsoft::fw::drivers
