#include "firmware/ports/stm32f4/spi.hpp"

#include <initializer_list>

#include "firmware/ports/stm32f4/gpio.hpp"
#include "firmware/ports/stm32f4/regs.hpp"

namespace nlsoft::fw::stm32f4 {

namespace {

using drivers::BusStatus;

constexpr uint32_t kCr1 = 0x00, kSr = 0x08, kDr = 0x0C;
constexpr uint32_t kMstr = 1u << 2, kSpe = 1u << 6, kSsi = 1u << 8, kSsm = 1u << 9;
constexpr uint32_t kRxne = 1u << 0, kTxe = 1u << 1, kModf = 1u << 5, kOvr = 1u << 6, kBsy = 1u << 7;
constexpr uint32_t kSpi1En = 1u << 12;  // APB2ENR
constexpr uint32_t kSpi2En = 1u << 14;  // APB1ENR
// The slowest rate (pclk / 256) moves a byte in 2048 APB clocks; a wait
// this long means the controller is not running.
constexpr uint32_t kByteWaitUs = 1000u;

// BR: rate = pclk / 2^(BR + 1), BR 0..7.
uint32_t baud_field(uint32_t pclk_hz, uint32_t max_hz) {
  uint32_t br = 0;
  while (br < 7u && (pclk_hz >> (br + 1u)) > max_hz) ++br;
  return br;
}

}  // namespace

Spi::Spi(const SpiBusPins& bus, const Clocks& clocks)
    : bus_(bus),
      pclk_hz_(bus.on_apb2 ? clocks.apb2_hz : clocks.apb1_hz),
      spins_(cortex_m::spins_for_us(clocks.core_hz, kByteWaitUs)) {}

uint32_t Spi::bit_rate_hz(uint32_t max_clock_hz) const {
  return pclk_hz_ >> (baud_field(pclk_hz_, max_clock_hz) + 1u);
}

void Spi::start() {
  uint32_t ports = gpio_clock_bit(bus_.sck.port);
  for (Pin p : kChipSelect) ports |= gpio_clock_bit(p.port);
  reg(rcc::kAhb1Enr) = reg(rcc::kAhb1Enr) | ports;
  const uint32_t enr = bus_.on_apb2 ? rcc::kApb2Enr : rcc::kApb1Enr;
  reg(enr) = reg(enr) | (bus_.on_apb2 ? kSpi1En : kSpi2En);
  settle(enr);
  for (Pin p : {bus_.sck, bus_.miso, bus_.mosi}) gpio_alternate(p, kSpiAf);
  // Every chip select high before any is an output: no chip sees a glitch.
  for (Pin p : kChipSelect) {
    gpio_write(p, true);
    gpio_output(p);
  }
}

BusStatus Spi::transfer(const drivers::SpiTarget& target, const uint8_t* tx, uint8_t* rx, size_t n) {
  if (target.cs >= kChipSelectCount || target.mode > 3 || target.max_clock_hz == 0) return BusStatus::kBusError;
  const uint32_t base = bus_.base;
  // Software slave select held high: the controller stays master; the chip
  // is selected by its GPIO alone.
  const uint32_t cr1 = kMstr | kSsm | kSsi | baud_field(pclk_hz_, target.max_clock_hz) << 3 | target.mode;
  if ((reg(base + kCr1) & ~kSpe) != cr1 || !(reg(base + kCr1) & kSpe)) {
    reg(base + kCr1) = cr1;  // format and rate change only while disabled
    reg(base + kCr1) = cr1 | kSpe;
  }
  if (reg(base + kSr) & kRxne) (void)uint32_t(reg(base + kDr));  // a byte left from an aborted transfer
  const Pin cs = kChipSelect[target.cs];
  gpio_write(cs, false);
  BusStatus status = BusStatus::kOk;
  for (size_t i = 0; i < n && status == BusStatus::kOk; ++i) {
    if (!wait_for([&] { return (reg(base + kSr) & kTxe) != 0; }, spins_)) {
      status = BusStatus::kTimeout;
      break;
    }
    reg(base + kDr) = tx ? tx[i] : 0u;
    if (!wait_for([&] { return (reg(base + kSr) & kRxne) != 0; }, spins_)) {
      status = BusStatus::kTimeout;
      break;
    }
    const uint8_t b = uint8_t(reg(base + kDr));
    if (rx) rx[i] = b;
    if (reg(base + kSr) & (kModf | kOvr)) status = BusStatus::kBusError;
  }
  // The last bit is out before the chip is released.
  if (!wait_for([&] { return (reg(base + kSr) & (kTxe | kBsy)) == kTxe; }, spins_) && status == BusStatus::kOk)
    status = BusStatus::kTimeout;
  gpio_write(cs, true);
  return status;
}

}  // namespace nlsoft::fw::stm32f4
