#include "firmware/ports/stm32f4/servo_usart.hpp"

#include "firmware/ports/cortex-m/board.hpp"
#include "firmware/ports/stm32f4/gpio.hpp"
#include "firmware/ports/stm32f4/part.hpp"
#include "firmware/ports/stm32f4/regs.hpp"

namespace nlsoft::fw::stm32f4 {

namespace {
constexpr uint32_t kSr = 0x00, kDr = 0x04, kBrr = 0x08, kCr1 = 0x0C, kCr3 = 0x14;
constexpr uint32_t kOre = 1u << 3, kRxne = 1u << 5, kTc = 1u << 6, kTxe = 1u << 7;
constexpr uint32_t kRe = 1u << 2, kTe = 1u << 3, kUe = 1u << 13;
constexpr uint32_t kHdsel = 1u << 3;
}  // namespace

ServoUsart::ServoUsart(const SerialBusPins& bus, const Clocks& clocks, uint32_t baud)
    : bus_(bus), pclk_hz_(clocks.apb2_hz != 0 ? clocks.apb2_hz : kHsiHz), baud_(baud != 0 ? baud : 1000000u),
      core_hz_(clocks.core_hz != 0 ? clocks.core_hz : kHsiHz),
      answer_us_(clocks.rcc_present ? kAnswerUs : kEmulatedAnswerUs),
      gap_us_(clocks.rcc_present ? kGapUs : kEmulatedGapUs),
      byte_spins_(cortex_m::spins_for_us(core_hz_, 20u + 20000000u / baud_)) {}

void ServoUsart::start() {
  reg(rcc::kAhb1Enr) = reg(rcc::kAhb1Enr) | gpio_clock_bit(bus_.tx.port);
  reg(rcc::kApb2Enr) = reg(rcc::kApb2Enr) | bus_.rcc_apb2_bit;
  settle(rcc::kApb2Enr);
  gpio_alternate(bus_.tx, bus_.af);
  gpio_open_drain(bus_.tx);
  const uint32_t shift = 2u * bus_.tx.number;
  reg(bus_.tx.port + 0x0C) = (reg(bus_.tx.port + 0x0C) & ~(3u << shift)) | (1u << shift);  // PUPDR: pull-up
  reg(base() + kBrr) = servo_brr(pclk_hz_, baud_);
  reg(base() + kCr3) = kHdsel;
  reg(base() + kCr1) = kUe | kTe;
}

// The receiver is off outside exchange(): only the data register's empty
// flag is waited on per byte, and the shift register's last byte (TC) only
// when an answer is to be listened for.
bool ServoUsart::transmit(const uint8_t* tx, size_t n, bool until_sent) {
  for (size_t i = 0; i < n; ++i) {
    if (!wait_for([&] { return (reg(base() + kSr) & kTxe) != 0; }, byte_spins_)) return false;
    reg(base() + kDr) = tx[i];
  }
  return !until_sent || wait_for([&] { return (reg(base() + kSr) & kTc) != 0; }, byte_spins_);
}

drivers::BusStatus ServoUsart::send(const uint8_t* tx, size_t n) {
  return transmit(tx, n, false) ? drivers::BusStatus::kOk : drivers::BusStatus::kTimeout;
}

drivers::BusStatus ServoUsart::exchange(const uint8_t* tx, size_t n, uint8_t* rx, size_t cap, size_t& got) {
  got = 0;
  if (n > 0) {
    if (!transmit(tx, n, true)) return drivers::BusStatus::kTimeout;
    // Whatever the receiver held from before is stale: SR then DR clears it.
    const uint32_t sr = reg(base() + kSr);
    const uint32_t dr = reg(base() + kDr);
    (void)sr;
    (void)dr;
  }
  reg(base() + kCr1) = kUe | kTe | kRe;
  const uint32_t hz = board::core_clock_hz() != 0 ? board::core_clock_hz() : core_hz_;
  const uint32_t answer = uint32_t(uint64_t(hz) * answer_us_ / 1000000u);
  const uint32_t gap = uint32_t(uint64_t(hz) * gap_us_ / 1000000u);
  uint32_t last = board::ticks();
  // Bounded twice: by the clock, and by a count of polls should the tick stand still.
  for (uint32_t polls = 0; got < cap && polls < 4u * answer; ++polls) {
    const uint32_t sr = reg(base() + kSr);
    if (sr & (kRxne | kOre)) {
      rx[got++] = uint8_t(reg(base() + kDr));
      last = board::ticks();
      continue;
    }
    if (board::ticks() - last > (got == 0 ? answer : gap)) break;
    // A breath between polls of the status register: a few core clocks on
    // silicon (a byte takes 1,680 at 1 Mbit/s), and under QEMU room for its
    // I/O thread to hand over the answer, which a register polled back to
    // back starves for milliseconds.
    for (volatile uint32_t i = 0; i < 32u; i = i + 1) {
    }
  }
  reg(base() + kCr1) = kUe | kTe;
  return got == 0 ? drivers::BusStatus::kTimeout : drivers::BusStatus::kOk;
}

}  // namespace nlsoft::fw::stm32f4
