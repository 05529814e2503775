#include "firmware/ports/mps2-an386/sbcon_i2c.hpp"

#include "firmware/ports/cortex-m/board.hpp"
#include "firmware/ports/cortex-m/wait.hpp"

namespace nlsoft::fw::an386 {

namespace {

using drivers::BusStatus;

constexpr uint32_t kScl = 1u << 0, kSda = 1u << 1;
// CONTROL (read) and CONTROLS (write: set) share offset 0; CONTROLC clears.
volatile uint32_t& control(uint32_t base) { return *reinterpret_cast<volatile uint32_t*>(base); }
volatile uint32_t& control_clear(uint32_t base) { return *reinterpret_cast<volatile uint32_t*>(base + 4u); }

// How long a chip may hold SCL low (clock stretching) before the bus is
// taken for stuck: SMBus's 25 ms per byte is the longest any chip here needs.
constexpr uint32_t kStretchUs = 25000u;

}  // namespace

SbconI2c::SbconI2c(uint32_t base, uint32_t core_hz, uint32_t bus_hz)
    : base_(base),
      half_ticks_(core_hz / (2u * bus_hz)),
      stretch_spins_(cortex_m::spins_for_us(core_hz, kStretchUs)) {
  control(base_) = kScl | kSda;  // both released: the bus idles high
}

void SbconI2c::half_period() const {
  // Bounded by polls too, should the tick stand still: each poll takes more
  // than one tick's worth of clocks on silicon, and 64 times that is slack
  // for an emulator that runs instructions faster than its clock.
  const uint32_t t0 = board::ticks();
  (void)cortex_m::wait_for([&] { return board::ticks() - t0 >= half_ticks_; }, 64u * half_ticks_ + 64u);
}

bool SbconI2c::clock_high() {
  control(base_) = kScl;
  return cortex_m::wait_for([&] { return (control(base_) & kScl) != 0; }, stretch_spins_);
}

// A chip left mid-byte by a reset holds SDA low: clock it out (at most nine
// bits) until it lets go, then STOP.
bool SbconI2c::idle_or_recovered() {
  if ((control(base_) & (kScl | kSda)) == (kScl | kSda)) return true;
  control(base_) = kSda;
  for (int i = 0; i < 9 && (control(base_) & kSda) == 0; ++i) {
    control_clear(base_) = kScl;
    half_period();
    if (!clock_high()) return false;
    half_period();
  }
  return stop() && (control(base_) & (kScl | kSda)) == (kScl | kSda);
}

// START from idle, or repeated START after a byte (SCL low).
bool SbconI2c::start() {
  control(base_) = kSda;
  half_period();
  if (!clock_high()) return false;
  half_period();
  control_clear(base_) = kSda;  // SDA falls while SCL is high
  half_period();
  control_clear(base_) = kScl;
  return true;
}

bool SbconI2c::stop() {
  control_clear(base_) = kScl;
  control_clear(base_) = kSda;
  half_period();
  if (!clock_high()) return false;
  half_period();
  control(base_) = kSda;  // SDA rises while SCL is high
  half_period();
  return true;
}

// SCL is low on entry and on return; the bit is read while SCL is high.
bool SbconI2c::send_byte(uint8_t byte, bool& acked) {
  for (int bit = 7; bit >= 0; --bit) {
    if (byte & (1u << bit))
      control(base_) = kSda;
    else
      control_clear(base_) = kSda;
    half_period();
    if (!clock_high()) return false;
    half_period();
    control_clear(base_) = kScl;
  }
  control(base_) = kSda;  // release SDA for the chip's acknowledge
  half_period();
  if (!clock_high()) return false;
  acked = (control(base_) & kSda) == 0;
  half_period();
  control_clear(base_) = kScl;
  return true;
}

bool SbconI2c::receive_byte(bool ack, uint8_t& byte) {
  control(base_) = kSda;
  byte = 0;
  for (int bit = 7; bit >= 0; --bit) {
    half_period();
    if (!clock_high()) return false;
    byte = uint8_t(byte << 1 | ((control(base_) & kSda) ? 1u : 0u));
    half_period();
    control_clear(base_) = kScl;
  }
  if (ack)
    control_clear(base_) = kSda;
  else
    control(base_) = kSda;  // NACK: the last byte wanted
  half_period();
  if (!clock_high()) return false;
  half_period();
  control_clear(base_) = kScl;
  control(base_) = kSda;
  return true;
}

BusStatus SbconI2c::write_read(uint8_t addr7, const uint8_t* w, size_t wn, uint8_t* r, size_t rn) {
  if (!idle_or_recovered()) return BusStatus::kTimeout;
  // A failed line wait mid-transaction leaves the bus to the next call's recovery.
  bool acked = false;
  const bool write_phase = wn > 0 || rn == 0;
  if (write_phase) {
    if (!start() || !send_byte(uint8_t(addr7 << 1), acked)) return BusStatus::kTimeout;
    for (size_t i = 0; acked && i < wn; ++i)
      if (!send_byte(w[i], acked)) return BusStatus::kTimeout;
  }
  if (rn > 0 && (acked || !write_phase)) {
    if (!start() || !send_byte(uint8_t(addr7 << 1 | 1u), acked)) return BusStatus::kTimeout;
    for (size_t i = 0; acked && i < rn; ++i)
      if (!receive_byte(i + 1 < rn, r[i])) return BusStatus::kTimeout;
  }
  if (!stop()) return BusStatus::kTimeout;
  return acked ? BusStatus::kOk : BusStatus::kNack;
}

}  // namespace nlsoft::fw::an386
