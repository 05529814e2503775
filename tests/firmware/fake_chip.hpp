#pragma once
// A sensor chip that answers what the test says (firmware/drivers/chip.hpp),
// counting the calls: the sampler's and the firmware's tests drive chips
// that go missing, answer wrongly or stop, without a bus.
#include "firmware/drivers/chip.hpp"

namespace nlsoft::test {

class FakeChip final : public fw::drivers::Chip {
 public:
  using Answer = fw::drivers::ChipStatus;
  explicit FakeChip(int channels) : channels_(channels) {}
  Answer begin_answer = Answer::kOk;
  Answer read_answer = Answer::kOk;
  float reading[fw::drivers::kMaxChipChannels] = {};
  int begins = 0, reads = 0;

  Answer begin() override {
    ++begins;
    return begin_answer;
  }
  Answer read(float* out) override {
    ++reads;
    if (read_answer == Answer::kOk)
      for (int c = 0; c < channels_; ++c) out[c] = reading[c];
    return read_answer;
  }
  int channels() const override { return channels_; }

 private:
  int channels_;
};

}  // namespace nlsoft::test
