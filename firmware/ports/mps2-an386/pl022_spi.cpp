#include "firmware/ports/mps2-an386/pl022_spi.hpp"

#include "firmware/ports/cortex-m/wait.hpp"

namespace nlsoft::fw::an386 {

namespace {

using drivers::BusStatus;

volatile uint32_t& at(uint32_t base, uint32_t offset) { return *reinterpret_cast<volatile uint32_t*>(base + offset); }
constexpr uint32_t kCr0 = 0x00, kCr1 = 0x04, kDr = 0x08, kSr = 0x0C, kCpsr = 0x10;
constexpr uint32_t kTnf = 1u << 1, kRne = 1u << 2, kBsy = 1u << 4;
constexpr uint32_t kSse = 1u << 1;
constexpr uint32_t kEightBits = 7u;  // DSS: data size - 1, Motorola frame format (FRF 0)
// Bit rate = clock / (CPSDVSR * (1 + SCR)), CPSDVSR even in 2..254, SCR 0..255.
constexpr uint32_t kPrescale = 2u;
// A byte at the slowest rate (clock / 512) takes 4096 clocks of the
// controller; a wait four times that long means it is not running.
constexpr uint32_t kByteWaitUs = 1000u;

uint32_t serial_clock_rate(uint32_t clock_hz, uint32_t max_hz) {
  const uint32_t divide = (clock_hz + kPrescale * max_hz - 1u) / (kPrescale * max_hz);  // rounded up: never above max
  return divide < 1u ? 0u : divide > 256u ? 255u : divide - 1u;
}

}  // namespace

Pl022Spi::Pl022Spi(uint32_t base, uint32_t clock_hz, uint32_t core_hz)
    : base_(base), clock_hz_(clock_hz), spins_(cortex_m::spins_for_us(core_hz, kByteWaitUs)) {}

uint32_t Pl022Spi::bit_rate_hz(uint32_t max_clock_hz) const {
  return clock_hz_ / (kPrescale * (1u + serial_clock_rate(clock_hz_, max_clock_hz)));
}

BusStatus Pl022Spi::transfer(const drivers::SpiTarget& target, const uint8_t* tx, uint8_t* rx, size_t n) {
  if (target.cs != 0 || target.mode > 3 || target.max_clock_hz == 0) return BusStatus::kBusError;
  const uint32_t cpol = target.mode >> 1, cpha = target.mode & 1u;
  const uint32_t cr0 = kEightBits | cpol << 6 | cpha << 7 | serial_clock_rate(clock_hz_, target.max_clock_hz) << 8;
  if (at(base_, kCr0) != cr0 || !(at(base_, kCr1) & kSse)) {
    at(base_, kCr1) = 0;  // format and rate change only while disabled
    at(base_, kCpsr) = kPrescale;
    at(base_, kCr0) = cr0;
    at(base_, kCr1) = kSse;  // master, enabled
  }
  // Bytes left from an aborted transfer would pose as this one's answer.
  for (int i = 0; i < 8 && (at(base_, kSr) & kRne); ++i) (void)uint32_t(at(base_, kDr));
  // One byte in flight at a time: the receive FIFO never overruns.
  for (size_t i = 0; i < n; ++i) {
    if (!cortex_m::wait_for([&] { return (at(base_, kSr) & kTnf) != 0; }, spins_)) return BusStatus::kTimeout;
    at(base_, kDr) = tx ? tx[i] : 0u;
    if (!cortex_m::wait_for([&] { return (at(base_, kSr) & kRne) != 0; }, spins_)) return BusStatus::kTimeout;
    const uint8_t b = uint8_t(at(base_, kDr));
    if (rx) rx[i] = b;
  }
  if (!cortex_m::wait_for([&] { return (at(base_, kSr) & kBsy) == 0; }, spins_)) return BusStatus::kTimeout;
  return BusStatus::kOk;
}

}  // namespace nlsoft::fw::an386
