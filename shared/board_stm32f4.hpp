#pragma once
// The stm32f4 board (a Nucleo-64) as a rig sees it: the timer channels that
// can drive an actuator and the ADC channels that can read a sensor. Both
// halves read this one description: the firmware's stm32f4 port drives and
// reads these pins, the console checks rig files against them
// (host/rig/board_pins.cpp) and generates an image's own wiring from them
// (which row drives actuator i, which reads sensor i, with the sensor's
// scaling: kRigPwm, kRigAnalogue in the image's nlsoft_rig.hpp). README.md
// prints the table for whoever wires the rig.
//
// Actuators: 20 kHz PWM over the platform's whole input range, duty =
// (u - u_min) / (u_max - u_min) with the rig file's limits ([[input]] min and
// max: hasel 0..1, tendon -1.2..1.2, msd -2000..2000 N), so a bidirectional input
// puts u = 0 at 50 %; a driver stage (MOSFET, HV amplifier, H-bridge) turns
// the duty into the actuator's input. Sensors: ADC1, 12 bits over 0..3.3 V, read
// continuously by DMA2 stream 0; l = offset + gain * volts. Sensor chips:
// on I2C1 or SPI1/SPI2 (kI2c, kSpi), each SPI chip on a chip-select pin of
// its own (kChipSelect, GPIO outputs driven low for a transfer).
#include <cstdint>

namespace nlsoft::fw::stm32f4 {

// The GPIO ports' register blocks (RM0390 memory map) and a pin on one.
constexpr uint32_t kGpioA = 0x40020000u, kGpioB = 0x40020400u, kGpioC = 0x40020800u;
struct Pin {
  uint32_t port;  // kGpioA, kGpioB, kGpioC
  uint8_t number;
};

struct PwmOutput {
  Pin pin;
  uint32_t timer;    // TIM3 or TIM4 base (APB1, AF2 on these pins)
  uint8_t channel;   // 1..4
};

struct AnalogueInput {
  Pin pin;
  uint8_t adc_channel;  // ADC1_IN<n>
  float offset, gain;   // sensor units = offset + gain * volts
};

constexpr uint32_t kTim3 = 0x40000400u, kTim4 = 0x40000800u;
constexpr uint32_t kTimers[] = {kTim3, kTim4};
constexpr uint32_t kPwmHz = 20000u;
constexpr float kAdcVref = 3.3f;

// PWM on TIM3 CH1-4 (PC6-PC9) and TIM4 CH1-2 (PB6-PB7): none of them is an
// ADC input, USART2, or the Nucleo's LED (PA5) and button (PC13).
constexpr PwmOutput kPwm[] = {
    {{kGpioC, 6}, kTim3, 1}, {{kGpioC, 7}, kTim3, 2}, {{kGpioC, 8}, kTim3, 3},
    {{kGpioC, 9}, kTim3, 4}, {{kGpioB, 6}, kTim4, 1}, {{kGpioB, 7}, kTim4, 2},
};

// The sixteen ADC1 inputs a Nucleo-64 brings out, in sensor order. PA2/PA3
// (IN2/IN3) carry USART2 and PA5 (IN5) the LED, so those three are absent.
constexpr AnalogueInput kAnalogue[] = {
    {{kGpioA, 0}, 0, 0.0f, 1.0f},   {{kGpioA, 1}, 1, 0.0f, 1.0f},   {{kGpioA, 4}, 4, 0.0f, 1.0f},
    {{kGpioA, 6}, 6, 0.0f, 1.0f},   {{kGpioA, 7}, 7, 0.0f, 1.0f},   {{kGpioB, 0}, 8, 0.0f, 1.0f},
    {{kGpioB, 1}, 9, 0.0f, 1.0f},   {{kGpioC, 0}, 10, 0.0f, 1.0f},  {{kGpioC, 1}, 11, 0.0f, 1.0f},
    {{kGpioC, 2}, 12, 0.0f, 1.0f},  {{kGpioC, 3}, 13, 0.0f, 1.0f},  {{kGpioC, 4}, 14, 0.0f, 1.0f},
    {{kGpioC, 5}, 15, 0.0f, 1.0f},
};

// The serial buses a sensor chip can hang on (RM0390 alternate-function
// table): I2C1 on PB8/PB9 (AF4, open-drain, the Arduino header's D15/D14),
// SPI1 on PA5/PA6/PA7 (AF5, APB2; D13/D12/D11) and SPI2 on PB13/PB14/PB15
// (AF5, APB1). SPI1 shares its pins with the LED (PA5) and ADC1_IN6/IN7
// (PA6/PA7): a rig uses SPI1 or those two analogue inputs, not both.
struct I2cBusPins {
  const char* name;
  uint32_t base;
  Pin scl, sda;
};
struct SpiBusPins {
  const char* name;
  uint32_t base;
  Pin sck, miso, mosi;
  bool on_apb2;  // clocked from APB2 (SPI1), else APB1
};
constexpr uint8_t kI2cAf = 4, kSpiAf = 5;
constexpr I2cBusPins kI2c[] = {{"i2c1", 0x40005400u, {kGpioB, 8}, {kGpioB, 9}}};
constexpr SpiBusPins kSpi[] = {
    {"spi1", 0x40013000u, {kGpioA, 5}, {kGpioA, 6}, {kGpioA, 7}, true},
    {"spi2", 0x40003800u, {kGpioB, 13}, {kGpioB, 14}, {kGpioB, 15}, false},
};
// The servo buses (Dynamixel): a USART in single-wire half-duplex mode
// (HDSEL) on its TX pin, open-drain with the pull-up the servos' line wants.
// USART1 on PB6 (AF7) and USART6 on PC6 (AF8), both on APB2: a rig drives
// servos or PWM on those pins, not both.
struct SerialBusPins {
  const char* name;
  uint32_t base;
  Pin tx;
  uint8_t af;
  uint8_t irq;
  uint32_t rcc_apb2_bit;
};
// The clock both USARTs run from (APB2) on each part the port builds for
// (F446, F411, F401: firmware/ports/stm32f4/part.hpp asserts its part's is
// here). A baud must come out of every one of them: the rig file does not
// say which part is on the board.
constexpr uint32_t kServoBusClocksHz[] = {90000000u, 100000000u, 84000000u};
// With 16x oversampling the divider (BRR) is clock / baud, at least 16; the
// baud it gives may miss the asked one by this much (Dynamixel's servos
// take a few per cent; 2 % leaves them margin).
constexpr float kServoBaudTolerance = 0.02f;
constexpr uint32_t servo_brr(uint32_t clock_hz, uint32_t baud) { return (clock_hz + baud / 2u) / baud; }
constexpr bool baud_reachable(uint32_t clock_hz, uint32_t baud) {
  const uint32_t brr = baud == 0u ? 0u : servo_brr(clock_hz, baud);
  if (brr < 16u || brr > 0xFFFFu) return false;
  const float got = float(clock_hz) / float(brr);
  const float miss = got > float(baud) ? got - float(baud) : float(baud) - got;
  return miss <= kServoBaudTolerance * float(baud);
}
constexpr SerialBusPins kServoBus[] = {
    {"usart1", 0x40011000u, {kGpioB, 6}, 7, 37, 1u << 4},
    {"usart6", 0x40011400u, {kGpioC, 6}, 8, 71, 1u << 5},
};

// Chip selects, in the order a rig's SpiTarget::cs counts them: free pins of
// the morpho and Arduino headers, none a PWM, ADC, bus, USART2, SWD or the
// button's pin.
constexpr Pin kChipSelect[] = {{kGpioB, 12}, {kGpioA, 8}, {kGpioA, 9}, {kGpioA, 10},
                               {kGpioB, 4},  {kGpioB, 5}, {kGpioB, 10}, {kGpioC, 10}};

// An actuator no pin drives and a sensor no channel reads (it reads 0).
constexpr PwmOutput kNoPwm = {{0, 0}, 0, 0};
constexpr uint8_t kNoChannel = 0xFF;
constexpr AnalogueInput kNoAnalogue = {{0, 0}, kNoChannel, 0.0f, 1.0f};

constexpr int kPwmCount = int(sizeof kPwm / sizeof kPwm[0]);
constexpr int kAnalogueCount = int(sizeof kAnalogue / sizeof kAnalogue[0]);
constexpr int kChipSelectCount = int(sizeof kChipSelect / sizeof kChipSelect[0]);
constexpr int kServoBusCount = int(sizeof kServoBus / sizeof kServoBus[0]);

}  // namespace nlsoft::fw::stm32f4
