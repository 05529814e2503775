#pragma once
// A sensor chip as the firmware samples it: checked and configured once at
// boot, read between control steps. Each driver (lis3mdl.hpp, dps310.hpp,
// ...) implements this over a bus from bus.hpp; what a chip can be set to
// (ranges, rates, channels, identity) is data in shared/chips/, which the
// rig loader checks a rig file against.
#include <cstddef>
#include <cstdint>

#include "firmware/drivers/bus.hpp"

namespace nlsoft::fw::drivers {

enum class ChipStatus : uint8_t {
  kOk = 0,
  kAbsent = 1,     // nothing answered at the chip's address or chip select
  kWrongId = 2,    // something answered, but its identity register is not the chip's
  kNotReady = 3,   // no new sample since the last read (data-ready clear); the old one stands
  kBusFault = 4,   // a transaction failed after the chip had answered (timeout, bus error)
  kBadConfig = 5,  // the driver's configuration names no bus, two buses, or a range/rate the chip lacks
  kFault = 6,      // it answered soundly and reports an error of its own (a servo's overload, overheating, voltage)
};

// The most channels one chip gives (a magnetometer's x, y, z; a pressure
// sensor's pressure and temperature; an ADC's inputs).
constexpr int kMaxChipChannels = 8;

class Chip {
 public:
  // Identity check, then configuration. kOk or why the chip cannot be used.
  virtual ChipStatus begin() = 0;
  // The newest sample, in the units shared/chips/ gives per channel, into
  // out[0 .. channels()). On anything but kOk, out is left untouched.
  virtual ChipStatus read(float* out) = 0;
  virtual int channels() const = 0;
  // After kFault: the names of what the chip reported (static strings,
  // "overload", ...), at most `max`; how many. A chip that reports nothing
  // of the kind names none.
  virtual size_t fault_names(const char** names, size_t max) const {
    (void)names;
    (void)max;
    return 0;
  }

 protected:
  ~Chip() = default;
};

}  // namespace nlsoft::fw::drivers
