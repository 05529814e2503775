#pragma once
// The real-board build: the link and the tick as on the HIL image; the
// actuators are timer PWM outputs and the sensors ADC1 inputs read by DMA,
// wired and scaled as the image's rig file says (kRigPwm, kRigAnalogue,
// generated into nlsoft_rig.hpp from the file's pwm and adc keys over the
// board's rows in shared/board_stm32f4.hpp). An actuator without a pin is computed but
// not driven; a sensor without a channel reads 0. The outputs are read in
// the same scan, after the sensors, when the rig file gives every output
// source = "adc" (kRigOutputAnalogue): read_output() then measures y, and
// the image says so (INFO's y_true capability); otherwise it reads none.
// The rig's sensor chips ([[device]]) hang on I2C1, SPI1 and SPI2
// (kI2c, kSpi), sampled between control steps (rig_chips.hpp). Its servos
// (Dynamixel, [[device]] on usart1 or usart6: kServoBus) are devices too,
// read between steps; an input a servo drives (kRigServoInputs) is written
// by one SYNC_WRITE per step instead of a PWM duty. A servo in `fault` is
// left out of it (held at its last goal), or released (torque off) once,
// as its device row says, until it answers ok again.
#include <new>
#include <type_traits>

#include "firmware/core/hal.hpp"
#include "firmware/ports/cortex-m/board.hpp"
#include "firmware/ports/cortex-m/platform_config.hpp"
#include "firmware/ports/cortex-m/rig_chips.hpp"
#include "firmware/ports/stm32f4/clock_tree.hpp"
#include "firmware/ports/stm32f4/gpio.hpp"
#include "firmware/ports/stm32f4/i2c1.hpp"
#include "firmware/ports/stm32f4/servo_usart.hpp"
#include "firmware/ports/stm32f4/spi.hpp"
#include "shared/board_stm32f4.hpp"

namespace nlsoft::fw::cortex_m {

template <int M, int W>
class RigHal final : public Hal {
  static_assert(M <= int(sizeof stm32f4::kRigPwm / sizeof stm32f4::kRigPwm[0]), "an actuator without a kRigPwm row");
  static constexpr int kRows = stm32f4::kRigAnalogueRows < W ? stm32f4::kRigAnalogueRows : W;
  // The conversions ADC1 scans: the wired sensors, in sensor order, then the outputs.
  static constexpr int scanned() {
    int count = 0;
    for (int i = 0; i < kRows; ++i) count += stm32f4::kRigAnalogue[i].adc_channel != stm32f4::kNoChannel;
    return count;
  }
  static constexpr int kSensorScans = scanned();
  static constexpr int kOutputs = stm32f4::kRigOutputRows;
  static_assert(kOutputs == 0 || kOutputs == int(kRig.n), "every output is read, or none");
  static constexpr int kAdcCount = kSensorScans + kOutputs;
  static_assert(kAdcCount <= 16, "ADC1 scans at most 16 conversions");

 public:
  // The image measures y (INFO advertises y_true) when the outputs are wired.
  static constexpr bool kMeasuresOutput = kOutputs > 0;

  size_t serial_read(uint8_t* buf, size_t cap) override { return board::serial_read(buf, cap); }
  size_t serial_write(const uint8_t* data, size_t len) override { return board::serial_write(data, len); }
  uint32_t ticks() override { return board::ticks(); }
  uint32_t tick_rate_hz() const override { return board::core_clock_hz(); }

  void actuate(const float* u, int m) override {
    if constexpr (kRigServoCount > 0) write_servos(u, m);
    if constexpr (kRigServoCount == M) return;  // every input a servo's: no PWM row to drive
    for (int i = 0; i < m && i < M; ++i) {
      const stm32f4::PwmOutput& o = stm32f4::kRigPwm[i];
      if (o.timer == 0) continue;
      float duty = (u[i] - kRig.u_min[i]) / (kRig.u_max[i] - kRig.u_min[i]);
      duty = duty > 0.0f ? (duty < 1.0f ? duty : 1.0f) : 0.0f;  // a NaN too: off, never an undefined cast
      stm32f4::reg(o.timer + 0x30u + 4u * o.channel) = uint32_t(duty * float(period_) + 0.5f);
    }
  }
  void read_sensors(float* l, int w) override {
    for (int i = 0, scan = 0; i < w; ++i) {
      if (i >= kRows || stm32f4::kRigAnalogue[i].adc_channel == stm32f4::kNoChannel) {
        l[i] = 0.0f;
        continue;
      }
      l[i] = scaled(stm32f4::kRigAnalogue[i], scan++);
    }
  }
  bool read_output(float* y, int n) override {
    if (!kMeasuresOutput || n > kOutputs) return false;
    for (int j = 0; j < n; ++j) y[j] = scaled(stm32f4::kRigOutputAnalogue[j], kSensorScans + j);
    return true;
  }

  void start() {
    using namespace stm32f4;
    reg(rcc::kAhb1Enr) = reg(rcc::kAhb1Enr) | gpio_clock_bit(kGpioA) | gpio_clock_bit(kGpioB) |
                         gpio_clock_bit(kGpioC) | kDma2En;
    reg(rcc::kApb1Enr) = reg(rcc::kApb1Enr) | kTim3En | kTim4En;
    reg(rcc::kApb2Enr) = reg(rcc::kApb2Enr) | kAdc1En;
    settle(rcc::kApb2Enr);
    start_pwm();
    if (kAdcCount > 0) start_adc();
    if constexpr (kRigDeviceCount > 0) start_chips(buses_);
  }
  void advance() {}
  // The sampler the firmware reads the chips through (an image with chips).
  SensorSampler& sensors() { return chips_.sampler(); }

 private:
  static constexpr uint32_t kDma2En = 1u << 22, kTim3En = 1u << 1, kTim4En = 1u << 2, kAdc1En = 1u << 8;

  // The value of conversion `scan` of the last DMA pass: offset + gain * volts.
  float scaled(const stm32f4::AnalogueInput& a, int scan) const {
    return a.offset + a.gain * float(raw_[scan]) * (stm32f4::kAdcVref / 4095.0f);
  }

  void start_pwm() {
    using namespace stm32f4;
    period_ = board_clocks().apb1_timer_hz / kPwmHz;
    for (uint32_t tim : kTimers) {
      reg(tim + 0x28) = 0;             // PSC: the timer clock itself
      reg(tim + 0x2C) = period_ - 1u;  // ARR
    }
    for (int i = 0; i < M; ++i) {
      const PwmOutput& o = kRigPwm[i];
      if (o.timer == 0) continue;
      gpio_alternate(o.pin, 2);  // AF2: TIM3/TIM4
      const uint32_t ccmr = o.timer + (o.channel <= 2 ? 0x18u : 0x1Cu);
      const uint32_t at = o.channel % 2 ? 0u : 8u;
      // PWM mode 1 with preload: a new duty starts with the next PWM period.
      reg(ccmr) = (reg(ccmr) & ~(0xFFu << at)) | ((6u << 4 | 1u << 3) << at);
      reg(o.timer + 0x30u + 4u * o.channel) = 0;  // until the first actuate(): off
      reg(o.timer + 0x20) = reg(o.timer + 0x20) | (1u << (4u * (o.channel - 1u)));  // CCER: output on
    }
    for (uint32_t tim : kTimers) {
      reg(tim + 0x14) = 1u;                  // EGR UG: load PSC/ARR now
      reg(tim + 0x00) = (1u << 7) | 1u;      // CR1: ARPE, counter on
    }
  }

  void start_adc() {
    using namespace stm32f4;
    constexpr uint32_t kAdc = 0x40012000u, kAdcCcr = 0x40012304u;
    constexpr uint32_t kDma = 0x40026400u, kS0Cr = kDma + 0x10, kS0Ndtr = kDma + 0x14, kS0Par = kDma + 0x18,
                       kS0M0ar = kDma + 0x1C, kLifcr = kDma + 0x08;
    uint32_t smpr1 = 0, smpr2 = 0, sq[3] = {0, 0, 0};
    int scan = 0;
    auto add = [&](const AnalogueInput& a) {
      gpio_analogue(a.pin);
      // 84 cycles per sample: source impedances up to ~20 kOhm settle.
      if (a.adc_channel < 10) smpr2 |= 4u << (3u * a.adc_channel);
      else smpr1 |= 4u << (3u * (a.adc_channel - 10u));
      sq[scan / 6] |= uint32_t(a.adc_channel) << (5u * uint32_t(scan % 6));
      ++scan;
    };
    for (int i = 0; i < kRows; ++i)
      if (kRigAnalogue[i].adc_channel != kNoChannel) add(kRigAnalogue[i]);
    for (int j = 0; j < kOutputs; ++j) add(kRigOutputAnalogue[j]);
    reg(kAdcCcr) = 1u << 16;  // ADCCLK = APB2 / 4: <= 36 MHz on all three parts
    reg(kAdc + 0x0C) = smpr1;
    reg(kAdc + 0x10) = smpr2;
    reg(kAdc + 0x34) = sq[0];                                     // SQR3: SQ1..6
    reg(kAdc + 0x30) = sq[1];                                     // SQR2: SQ7..12
    reg(kAdc + 0x2C) = sq[2] | (uint32_t(kAdcCount - 1) << 20);  // SQR1: SQ13..16, length
    reg(kAdc + 0x04) = 1u << 8;                                   // CR1: scan

    // DMA2 stream 0, channel 0 (ADC1): circular, 16-bit, into raw_.
    reg(kS0Cr) = 0;
    (void)wait_for([] { return (reg(kDma + 0x10) & 1u) == 0; });
    reg(kLifcr) = 0x3Du;
    reg(kS0Par) = kAdc + 0x4C;  // ADC1 DR
    reg(kS0M0ar) = uint32_t(reinterpret_cast<uintptr_t>(raw_));
    reg(kS0Ndtr) = uint32_t(kAdcCount);
    reg(kS0Cr) = (1u << 13) | (1u << 11) | (1u << 10) | (1u << 8) | 1u;  // MSIZE/PSIZE 16, MINC, CIRC, EN

    // ADON, continuous, DMA with DDS (requests keep coming in circular mode).
    reg(kAdc + 0x08) = 1u | (1u << 1) | (1u << 8) | (1u << 9);
    // The converter needs t_STAB (3 us, 540 cycles at 180 MHz) after ADON
    // before a start is taken: 2000 turns of a volatile loop are several
    // times that on every part, and no timer is free here to wait on.
    for (volatile uint32_t i = 0; i < 2000u; i = i + 1) {
    }
    reg(kAdc + 0x08) = reg(kAdc + 0x08) | (1u << 30);  // SWSTART
  }

  static constexpr int kSerialCount = int(sizeof stm32f4::kServoBus / sizeof stm32f4::kServoBus[0]);
  static constexpr int kBusesBeforeSerial =
      int(sizeof stm32f4::kI2c / sizeof stm32f4::kI2c[0]) + int(sizeof stm32f4::kSpi / sizeof stm32f4::kSpi[0]);

  // The goals of the servo-driven inputs, in one SYNC_WRITE per protocol on
  // each servo bus (a rig's servos share one bus: the loader holds them to
  // one baud per bus, and a board image drives the buses its devices name).
  void write_servos(const float* u, int m) {
    for (int b = 0; b < kSerialCount; ++b) {
      if (serial_[b] == nullptr) continue;
      drivers::ServoGoal goals[drivers::kMaxGoals];
      size_t n = 0;
      for (int i = 0; i < m && i < M; ++i) {
        const RigServoInput& s = kRigServoInputs[i];
        if (s.device == kNoServo || kRigDevices[s.device].bus != kBusesBeforeSerial + b) continue;
        const RigDeviceConfig& c = kRigDevices[s.device];
        // A servo that reported a fault gets no new goal until it answers
        // again without one (ok): not while it is silent or garbled after it.
        const uint32_t bit = 1u << s.device;
        const DeviceState state = chips_.sampler().state(s.device);
        if (state == DeviceState::Fault) held_ |= bit;
        if (state == DeviceState::Ok) {
          held_ &= ~bit;
          released_ &= ~bit;
        }
        if (held_ & bit) {
          release_once(s.device, c);
          continue;  // held at its last goal (or released)
        }
        const drivers::dynamixel::TickMapping map{s.goal_at_neutral - s.goal_per_unit * s.neutral, s.goal_per_unit, 0,
                                                  int32_t(c.chip->goal_max)};
        int32_t goal = 0;
        if (n < drivers::kMaxGoals && drivers::dynamixel::goal_ticks(map, u[i], &goal))
          goals[n++] = drivers::ServoGoal{c.address, c.chip->servo_protocol, uint32_t(goal)};
      }
      if (n > 0) (void)drivers::write_goals(*serial_[b], goals, n);
    }
  }
  // A servo whose row says release goes limp once per fault.
  void release_once(int d, const RigDeviceConfig& c) {
    if (!c.release_on_fault || (released_ & (1u << d))) return;
    if (auto* servo = static_cast<drivers::DynamixelServo*>(chips_.chip(d))) (void)servo->torque(false);
    released_ |= 1u << d;
  }

  // The masters of the buses the rig's chips use (I2C1 at the slowest clock
  // its chips take), then the drivers over them.
  static constexpr bool uses(BusKind kind) {
    for (int d = 0; d < kRigDeviceCount; ++d)
      if (kRigDevices[d].kind == kind) return true;
    return false;
  }

  template <class Buses>
  void start_chips(Buses& buses) {
    using namespace stm32f4;
    constexpr int kI2cCount = int(sizeof kI2c / sizeof kI2c[0]), kSpiCount = int(sizeof kSpi / sizeof kSpi[0]);
    static_assert(kI2cCount == 1, "one I2C master: I2c1");
    drivers::I2cBus* i2c[kI2cCount] = {};
    drivers::SpiBus* spi[kSpiCount] = {};
    uint32_t i2c_hz = 400000u;
    bool spi_used[kSpiCount] = {};
    for (int d = 0; d < kRigDeviceCount; ++d) {
      const RigDeviceConfig& c = kRigDevices[d];
      if (c.kind == BusKind::I2c) {
        if (c.clock_hz < i2c_hz) i2c_hz = c.clock_hz;
      } else if (c.bus >= kI2cCount && c.bus < kI2cCount + kSpiCount) {
        spi_used[c.bus - kI2cCount] = true;
      }
    }
    // At compile time: an image without an I2C chip links no I2C master,
    // one without a servo no USART master (nor its 64-bit baud division).
    if constexpr (uses(BusKind::I2c)) {
      I2c1* bus = new (&buses.i2c.bus) I2c1(board_clocks(), i2c_hz);
      bus->start();
      i2c[0] = bus;
    }
    for (int b = 0; b < kSpiCount; ++b) {
      if (!spi_used[b]) continue;
      Spi* bus = new (&buses.spi[b].bus) Spi(kSpi[b], board_clocks());
      bus->start();
      spi[b] = bus;
    }
    if constexpr (uses(BusKind::Serial))
      for (int d = 0; d < kRigDeviceCount; ++d) {
        const RigDeviceConfig& c = kRigDevices[d];
        const int b = c.bus - kI2cCount - kSpiCount;
        if (c.kind != BusKind::Serial || b < 0 || b >= kSerialCount || serial_[b] != nullptr) continue;
        ServoUsart* bus = new (&buses.serial[b].bus) ServoUsart(kServoBus[b], board_clocks(), c.clock_hz);
        bus->start();
        serial_[b] = bus;
      }
    chips_.start(i2c, kI2cCount, spi, kSpiCount, serial_, kSerialCount);
  }

  // Raw storage: the masters take the clock tree, known only once the board started.
  union I2cSlot {
    I2cSlot() {}
    ~I2cSlot() {}
    stm32f4::I2c1 bus;
  };
  union SpiSlot {
    SpiSlot() {}
    ~SpiSlot() {}
    stm32f4::Spi bus;
  };
  union SerialSlot {
    SerialSlot() {}
    ~SerialSlot() {}
    stm32f4::ServoUsart bus;
  };

  uint32_t period_ = 1;
  volatile uint16_t raw_[kAdcCount > 0 ? kAdcCount : 1] = {};
  struct Buses {
    I2cSlot i2c;
    SpiSlot spi[sizeof stm32f4::kSpi / sizeof stm32f4::kSpi[0]];
    SerialSlot serial[sizeof stm32f4::kServoBus / sizeof stm32f4::kServoBus[0]];
  };
  struct NoBuses {};
  // Room for the masters in an image with chips only.
  [[no_unique_address]] std::conditional_t<(kRigDeviceCount > 0), Buses, NoBuses> buses_;
  RigChips<kRigDeviceCount, W, kRigDevices> chips_{kRigSensorSources};
  drivers::SerialBus* serial_[kSerialCount] = {};
  uint32_t held_ = 0;      // bit d: servo d faulted and has not answered ok since
  uint32_t released_ = 0;  // bit d: servo d was released for its current fault
};

}  // namespace nlsoft::fw::cortex_m
