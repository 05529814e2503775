#pragma once
// The sensor chips of a rig, sampled ahead of the control step. At boot
// every chip is checked and configured (Chip::begin); between steps
// (Firmware::poll) each chip whose next sample is due is read, one after the
// other, so the step itself never touches a bus: it takes the latest sample
// of each channel and its age (fill). A chip that is absent, answers with
// another identity, or stops answering (a failed read, or no new sample for
// four of its periods plus 100 ms; a chip without a rate, only the former)
// has its channels marked invalid: they hold their last good value (their
// offset before the first) and say so, never a silent 0. A failed chip is
// tried again (begin) at most once a second. Works with any Chip: the port
// owns the drivers and the buses, the image's rig header the tables.
#include <cstdint>

#include "firmware/drivers/chip.hpp"
#include "protocol/messages.hpp"
#include "shared/rig_devices.hpp"

namespace nlsoft::fw {

// A device's state as DEVICE_STATUS carries it (PROTOCOL.md 7): ok;
// absent (nothing answered at its address or chip select); wrong id
// (something answered, with another identity); stopped (it answered, then
// a read failed or no new sample came); fault (it answers, reporting an
// error of its own: a servo's overload).
using DeviceState = protocol::DeviceState;

// What the step gets besides the values: which sensor channels are
// invalid (bit i: channel i) and the age of the oldest valid chip sample,
// kNoValidSample when no channel read from a chip is valid (SENSOR_HEALTH's
// 65535: never 0, which is a fresh sample's age).
struct SensorHealth {
  static constexpr uint32_t kNoValidSample = UINT32_MAX;
  uint32_t invalid = 0;
  uint32_t age_ms = kNoValidSample;
};

class SensorSampler {
 public:
  static constexpr int kMaxDevices = kRigMaxDevices;
  static constexpr uint32_t kRetryMs = 1000;
  static constexpr int kMaxChannels = 32;  // sensor channels: SENSOR_HEALTH's mask is a u32

  // What the sampler keeps per chip; the caller holds one per device, so an
  // image pays for its own chips only.
  struct Slot {
    protocol::DeviceState state = protocol::DeviceState::Absent;
    bool sampled = false, begun = false;
    uint32_t tried_ms = 0, sample_ms = 0, faults = 0;
    float value[drivers::kMaxChipChannels] = {};
  };

  // chips[d] is device d of `devices` (the image's table), `count` of them,
  // slots[d] its state; sources[i] says where sensor channel i is read, `w`
  // of them. All pointers outlive the sampler.
  SensorSampler(drivers::Chip* const* chips, const RigDeviceConfig* devices, Slot* slots, int count,
                const RigSensorSource* sources, int w)
      : chips_(chips), devices_(devices), slots_(slots), count_(count < kMaxDevices ? count : kMaxDevices),
        sources_(sources), w_(w < kMaxChannels ? w : kMaxChannels) {}

  void begin(uint32_t now_ms) {
    for (int d = 0; d < count_; ++d) start(d, now_ms);
  }

  // Between steps: reads each chip whose sample is due, retries each failed
  // chip whose retry is due. Each chip's transactions are bounded (bus.hpp).
  void poll(uint32_t now_ms) {
    for (int k = 0; k < count_; ++k) {
      const int d = (next_ + k) % count_;
      Slot& s = slots_[d];
      if (s.state != DeviceState::Ok) {
        if (now_ms - s.tried_ms >= kRetryMs) start(d, now_ms);
        continue;
      }
      if (now_ms - s.tried_ms < period_ms(d)) continue;
      s.tried_ms = now_ms;
      read(d, now_ms);
    }
    next_ = count_ > 0 ? (next_ + 1) % count_ : 0;
  }

  // For the step: the chip channels into l (offset + gain * reading; an
  // invalid one holds its last good value), other channels untouched.
  SensorHealth fill(float* l, uint32_t now_ms) const {
    SensorHealth h;
    uint32_t oldest = 0;
    bool any_valid = false;
    for (int i = 0; i < w_; ++i) {
      const RigSensorSource& src = sources_[i];
      if (src.from != SensorFrom::Device || src.device >= count_) continue;
      const Slot& s = slots_[src.device];
      if (s.state != DeviceState::Ok || !s.sampled) {
        h.invalid |= 1u << i;
      } else {
        any_valid = true;
        if (now_ms - s.sample_ms > oldest) oldest = now_ms - s.sample_ms;
      }
      // Before the chip's first good sample its reading is 0: the channel
      // holds its offset (flagged invalid).
      l[i] = src.offset + src.gain * s.value[src.channel];
    }
    if (any_valid) h.age_ms = oldest;
    return h;
  }

  int count() const { return count_; }
  const RigDeviceConfig& device(int d) const { return devices_[d]; }
  DeviceState state(int d) const { return slots_[d].state; }
  // Milliseconds since device d's latest sample; UINT32_MAX before its first.
  uint32_t age_ms(int d, uint32_t now_ms) const {
    return slots_[d].sampled ? now_ms - slots_[d].sample_ms : UINT32_MAX;
  }
  // Failed begins and reads of device d since boot.
  uint32_t faults(int d) const { return slots_[d].faults; }
  // What device d in `fault` reported (a servo's error bits), at most `max` names.
  size_t fault_names(int d, const char** names, size_t max) const { return chips_[d]->fault_names(names, max); }

  // The device take_change() would return, left pending: the firmware
  // takes a change only once its LOG is queued.
  int peek_change() const {
    for (int d = 0; d < count_; ++d)
      if (changed_ & (1u << d)) return d;
    return -1;
  }

  // The next device whose state changed since it was last taken, or -1:
  // the firmware logs each change once.
  int take_change() {
    for (int d = 0; d < count_; ++d)
      if (changed_ & (1u << d)) {
        changed_ &= ~(1u << d);
        return d;
      }
    return -1;
  }

 private:
  // A chip's sample is due once per period of its data rate; a chip without
  // one (an ADC converts on demand) at every poll.
  uint32_t period_ms(int d) const {
    const float r = devices_[d].rate.value;
    return r > 0.0f ? uint32_t(1000.0f / r) : 0u;
  }
  // No new sample for four periods (and 100 ms, the slowest poll a busy
  // link allows): the chip has stopped.
  uint32_t stale_ms(int d) const { return 4u * period_ms(d) + 100u; }

  void start(int d, uint32_t now_ms) {
    Slot& s = slots_[d];
    s.tried_ms = now_ms;
    const drivers::ChipStatus r = chips_[d]->begin();
    if (r != drivers::ChipStatus::kOk) ++s.faults;
    set(d, r == drivers::ChipStatus::kOk        ? DeviceState::Ok
           : r == drivers::ChipStatus::kWrongId ? DeviceState::WrongId
           : r == drivers::ChipStatus::kBusFault ? DeviceState::Stopped
           : r == drivers::ChipStatus::kFault    ? DeviceState::Fault
                                                 : DeviceState::Absent);
    // A chip back from a fault starts its staleness afresh.
    if (s.state == DeviceState::Ok) s.sample_ms = now_ms;
  }

  void read(int d, uint32_t now_ms) {
    Slot& s = slots_[d];
    float v[drivers::kMaxChipChannels];
    const drivers::ChipStatus r = chips_[d]->read(v);
    if (r == drivers::ChipStatus::kOk) {
      const int n = chips_[d]->channels() < drivers::kMaxChipChannels ? chips_[d]->channels()
                                                                       : drivers::kMaxChipChannels;
      for (int c = 0; c < n; ++c) s.value[c] = v[c];
      s.sampled = true;
      s.sample_ms = now_ms;
      return;
    }
    if (r == drivers::ChipStatus::kNotReady && now_ms - s.sample_ms < stale_ms(d)) return;
    ++s.faults;
    set(d, r == drivers::ChipStatus::kWrongId ? DeviceState::WrongId
           : r == drivers::ChipStatus::kFault ? DeviceState::Fault
                                              : DeviceState::Stopped);
  }

  // A change is logged once; at boot only a chip that is not ok is news.
  void set(int d, DeviceState state) {
    Slot& s = slots_[d];
    if (s.begun ? s.state != state : state != DeviceState::Ok) changed_ |= 1u << d;
    s.begun = true;
    s.state = state;
  }

  drivers::Chip* const* chips_;
  const RigDeviceConfig* devices_;
  Slot* slots_;
  int count_;
  const RigSensorSource* sources_;
  int w_;
  uint32_t changed_ = 0;
  int next_ = 0;
};

}  // namespace nlsoft::fw
