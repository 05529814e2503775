#pragma once
// Status codes shared by the controller, the model loader and the parameter
// table. The protocol carries them as one byte, so values are stable.
#include <cstdint>

namespace nlsoft {

enum class Status : uint8_t {
  Ok = 0,
  OutOfRange = 1,      // a value outside its [min, max]
  NotFinite = 2,       // NaN or Inf where a finite number is required
  WrongSize = 3,       // element count does not match the parameter or buffer
  UnknownId = 4,       // no such parameter / layer kind / activation
  Inconsistent = 5,    // valid alone, invalid together (Nc > N, u_min >= u_max, ...)
  TooLarge = 6,        // exceeds a compile-time capacity
  BadFormat = 7,       // malformed model file / table
  BadChecksum = 8,     // CRC mismatch
  Unsupported = 10,    // a model shape this build has no kernel for (capacity.hpp)
};

inline const char* status_name(Status s) {
  switch (s) {
    case Status::Ok: return "ok";
    case Status::OutOfRange: return "out of range";
    case Status::NotFinite: return "not finite";
    case Status::WrongSize: return "wrong size";
    case Status::UnknownId: return "unknown id";
    case Status::Inconsistent: return "inconsistent";
    case Status::TooLarge: return "exceeds capacity";
    case Status::BadFormat: return "bad format";
    case Status::BadChecksum: return "bad checksum";
    case Status::Unsupported: return "no kernel for this model shape in this build";
  }
  return "unknown status";
}

}  // namespace nlsoft
