#include "firmware/ports/stm32f4/i2c1.hpp"

#include <initializer_list>

#include "firmware/ports/stm32f4/gpio.hpp"
#include "firmware/ports/stm32f4/regs.hpp"

namespace nlsoft::fw::stm32f4 {

namespace {

using drivers::BusStatus;

constexpr I2cBusPins kBus = kI2c[0];
constexpr uint32_t kCr1 = kBus.base + 0x00, kCr2 = kBus.base + 0x04, kDr = kBus.base + 0x10;
constexpr uint32_t kSr1 = kBus.base + 0x14, kSr2 = kBus.base + 0x18, kCcr = kBus.base + 0x1C;
constexpr uint32_t kTrise = kBus.base + 0x20;
constexpr uint32_t kPe = 1u << 0, kStart = 1u << 8, kStop = 1u << 9, kAck = 1u << 10, kPos = 1u << 11;
constexpr uint32_t kSwrst = 1u << 15;
constexpr uint32_t kSb = 1u << 0, kAddr = 1u << 1, kBtf = 1u << 2, kRxne = 1u << 6, kTxe = 1u << 7;
constexpr uint32_t kBerr = 1u << 8, kArlo = 1u << 9, kAf = 1u << 10;
constexpr uint32_t kBusy = 1u << 1;
constexpr uint32_t kFastMode = 1u << 15;
constexpr uint32_t kI2c1En = 1u << 21;
// A byte at 100 kHz takes 90 µs; a chip may stretch SCL for more (SMBus
// allows 25 ms). Past that the bus is taken for stuck.
constexpr uint32_t kFlagWaitUs = 25000u;
// While recovering, a chip holding SCL low past this is left to the next try.
constexpr uint32_t kRecoverStretchUs = 1000u;

uint32_t ccr_for(uint32_t apb1_hz, uint32_t bus_hz) {
  // Standard mode: T_high = T_low = CCR / f; fast mode (duty 2:1): 3 CCR / f.
  const uint32_t per = bus_hz > 100000u ? 3u * bus_hz : 2u * bus_hz;
  uint32_t ccr = (apb1_hz + per - 1u) / per;  // rounded up: never faster than asked
  const uint32_t least = bus_hz > 100000u ? 1u : 4u;
  if (ccr < least) ccr = least;
  return (ccr & 0xFFFu) | (bus_hz > 100000u ? kFastMode : 0u);
}

}  // namespace

I2c1::I2c1(const Clocks& clocks, uint32_t bus_hz)
    : clocks_(clocks), bus_hz_(bus_hz), spins_(cortex_m::spins_for_us(clocks.core_hz, kFlagWaitUs)) {}

uint32_t I2c1::bus_hz() const {
  const uint32_t ccr = ccr_for(clocks_.apb1_hz, bus_hz_);
  return clocks_.apb1_hz / ((ccr & kFastMode ? 3u : 2u) * (ccr & 0xFFFu));
}

void I2c1::start() {
  reg(rcc::kAhb1Enr) = reg(rcc::kAhb1Enr) | gpio_clock_bit(kGpioB);
  reg(rcc::kApb1Enr) = reg(rcc::kApb1Enr) | kI2c1En;
  settle(rcc::kApb1Enr);
  for (Pin p : {kBus.scl, kBus.sda}) {
    gpio_open_drain(p);
    gpio_alternate(p, kI2cAf);
  }
  reg(kCr1) = kSwrst;  // out of whatever state a timeout left
  reg(kCr1) = 0;
  const uint32_t mhz = clocks_.apb1_hz / 1000000u;
  reg(kCr2) = mhz & 0x3Fu;
  reg(kCcr) = ccr_for(clocks_.apb1_hz, bus_hz_);
  // Rise time 1000 ns (standard) or 300 ns (fast), in APB1 clocks, plus one.
  reg(kTrise) = (bus_hz_ > 100000u ? mhz * 300u / 1000u : mhz) + 1u;
  reg(kCr1) = kPe;
}

// A chip reset mid-byte can hold SDA low forever: clock SCL by hand until it
// lets go (nine clocks finish any byte and its acknowledge), then STOP.
void I2c1::recover() {
  reg(kCr1) = 0;
  for (Pin p : {kBus.scl, kBus.sda}) {
    gpio_write(p, true);
    gpio_output(p);
  }
  const uint32_t half = clocks_.core_hz / (2u * bus_hz_);  // polls of one clock or more: half a bit at least
  for (int i = 0; i < 9 && !gpio_read(kBus.sda); ++i) {
    gpio_write(kBus.scl, false);
    (void)wait_for([] { return false; }, half);
    gpio_write(kBus.scl, true);
    (void)wait_for([] { return gpio_read(kBus.scl); }, cortex_m::spins_for_us(clocks_.core_hz, kRecoverStretchUs));
    (void)wait_for([] { return false; }, half);
  }
  gpio_write(kBus.sda, false);
  (void)wait_for([] { return false; }, half);
  gpio_write(kBus.sda, true);  // STOP: SDA rises while SCL is high
  start();
}

BusStatus I2c1::wait_sr1(uint32_t flags) {
  uint32_t sr1 = 0;
  const bool came = wait_for([&] { return ((sr1 = reg(kSr1)) & (flags | kAf | kBerr | kArlo)) != 0; }, spins_);
  if (!came) return BusStatus::kTimeout;
  if (sr1 & kAf) return BusStatus::kNack;
  if (sr1 & (kBerr | kArlo)) return BusStatus::kBusError;
  return BusStatus::kOk;
}

// START, then the address byte; ADDR is left set (the caller clears it).
BusStatus I2c1::address(uint8_t byte) {
  reg(kCr1) = reg(kCr1) | kStart;
  if (const BusStatus s = wait_sr1(kSb); s != BusStatus::kOk) return s;
  reg(kDr) = byte;
  return wait_sr1(kAddr);
}

// RM0390 27.3.3's closing sequences: the NACK and STOP must be set before
// the last byte's acknowledge slot, which differs for 1, 2 and more bytes.
BusStatus I2c1::receive(uint8_t* r, size_t rn) {
  auto clear_addr = [] { (void)uint32_t(reg(kSr1)), (void)uint32_t(reg(kSr2)); };
  if (rn == 1) {
    reg(kCr1) = reg(kCr1) & ~kAck;
    clear_addr();
    reg(kCr1) = reg(kCr1) | kStop;
    if (const BusStatus s = wait_sr1(kRxne); s != BusStatus::kOk) return s;
    r[0] = uint8_t(reg(kDr));
    return BusStatus::kOk;
  }
  if (rn == 2) {
    // POS: the NACK goes with the second byte, the one after the shift register's.
    reg(kCr1) = (reg(kCr1) & ~kAck) | kPos;
    clear_addr();
    if (const BusStatus s = wait_sr1(kBtf); s != BusStatus::kOk) return s;
    reg(kCr1) = reg(kCr1) | kStop;
    r[0] = uint8_t(reg(kDr));
    r[1] = uint8_t(reg(kDr));
    reg(kCr1) = reg(kCr1) & ~kPos;
    return BusStatus::kOk;
  }
  reg(kCr1) = reg(kCr1) | kAck;
  clear_addr();
  for (size_t i = 0; i + 3 < rn; ++i) {
    if (const BusStatus s = wait_sr1(kRxne); s != BusStatus::kOk) return s;
    r[i] = uint8_t(reg(kDr));
  }
  // Byte N-2 in DR, N-1 in the shift register, the bus stretched.
  if (const BusStatus s = wait_sr1(kBtf); s != BusStatus::kOk) return s;
  reg(kCr1) = reg(kCr1) & ~kAck;
  r[rn - 3] = uint8_t(reg(kDr));
  reg(kCr1) = reg(kCr1) | kStop;
  r[rn - 2] = uint8_t(reg(kDr));
  if (const BusStatus s = wait_sr1(kRxne); s != BusStatus::kOk) return s;
  r[rn - 1] = uint8_t(reg(kDr));
  return BusStatus::kOk;
}

BusStatus I2c1::transact(uint8_t addr7, const uint8_t* w, size_t wn, uint8_t* r, size_t rn) {
  if (!wait_for([] { return (reg(kSr2) & kBusy) == 0; }, spins_)) return BusStatus::kTimeout;
  if (wn > 0 || rn == 0) {
    if (const BusStatus s = address(uint8_t(addr7 << 1)); s != BusStatus::kOk) return s;
    (void)uint32_t(reg(kSr2));  // ADDR cleared by SR1 then SR2
    for (size_t i = 0; i < wn; ++i) {
      if (const BusStatus s = wait_sr1(kTxe); s != BusStatus::kOk) return s;
      reg(kDr) = w[i];
    }
    if (const BusStatus s = wait_sr1(wn > 0 ? kBtf : kTxe); s != BusStatus::kOk) return s;
  }
  if (rn > 0) {
    if (const BusStatus s = address(uint8_t(addr7 << 1 | 1u)); s != BusStatus::kOk) return s;
    if (const BusStatus s = receive(r, rn); s != BusStatus::kOk) return s;
  } else {
    reg(kCr1) = reg(kCr1) | kStop;
  }
  // STOP clears itself once on the wire; the next START must not come sooner.
  return wait_for([] { return (reg(kCr1) & kStop) == 0; }, spins_) ? BusStatus::kOk : BusStatus::kTimeout;
}

BusStatus I2c1::write_read(uint8_t addr7, const uint8_t* w, size_t wn, uint8_t* r, size_t rn) {
  const BusStatus s = transact(addr7, w, wn, r, rn);
  switch (s) {
    case BusStatus::kOk:
      break;
    case BusStatus::kNack:  // the chip let go of the bus: end it here
      reg(kSr1) = reg(kSr1) & ~kAf;
      reg(kCr1) = (reg(kCr1) & ~(kAck | kPos)) | kStop;
      (void)wait_for([] { return (reg(kCr1) & kStop) == 0; }, spins_);
      break;
    case BusStatus::kTimeout:
    case BusStatus::kBusError:
      recover();
      break;
  }
  return s;
}

}  // namespace nlsoft::fw::stm32f4
