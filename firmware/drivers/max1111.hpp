#pragma once
// Maxim MAX1111 4-channel 8-bit ADC (shared/chips/max1111.hpp) on SPI: the
// four inputs in volts, single-ended against COM, unipolar (0 .. reference).
//
// One transfer converts all four: per channel a control byte (START, the
// channel's SEL bits, unipolar, single-ended, PD1 PD0 = 11: powered, external
// clock) then two bytes in which the 24-clock frame returns the result as
// 0 0 D7..D2 | D1 D0 0 0 0 0 0 0 (the datasheet's external-clock timing; QEMU's max111x model
// answers the same frame).
//
// What can be told about the chip, having no identity register: a frame
// whose framing bits are not zero is no MAX1111's (an absent chip on a
// pulled-up MISO reads all ones): kAbsent at begin(), kBusFault after. A
// MISO that floats low reads as every input at 0 V, a legal answer, and
// cannot be told from a chip; neither can a MAX1110 or another 8-bit ADC of
// the family answering the same frame.
#include <cstdint>

#include "firmware/drivers/bus.hpp"
#include "firmware/drivers/chip.hpp"
#include "shared/chips/max1111.hpp"

namespace nlsoft::fw::drivers {

class Max1111 final : public Chip {
 public:
  static constexpr float kInternalReferenceVolts = 2.048f;

  struct Config {
    SpiBus* spi = nullptr;
    SpiTarget target{};
    // The full scale: the internal reference unless REFADJ is tied to VDD
    // and REF driven from outside (1 V .. VDD).
    float reference_volts = kInternalReferenceVolts;
  };

  static constexpr int kChannels = 4;
  static constexpr int kFrameBytes = 3;

  explicit Max1111(const Config& config) : config_(config) {}

  ChipStatus begin() override;
  ChipStatus read(float* out) override;
  int channels() const override { return kChannels; }

  // The control byte that converts input `channel` (0..3): SEL2 is the
  // channel's low bit, SEL1 its high bit (the datasheet's channel table).
  static uint8_t control_byte(int channel);

 private:
  // The four codes, or false when a frame's framing bits are set.
  bool convert(uint8_t codes[kChannels], BusStatus& status);

  Config config_;
  ChipStatus state_ = ChipStatus::kNotReady;  // begin()'s last answer; read() gives it until kOk
};

}  // namespace nlsoft::fw::drivers
