#pragma once
// Status codes. Two families that must not be confused:
//  - StatusCode travels on the wire inside NACK (and is what pack/unpack
//    return, so a request handler can NACK with it directly);
//  - FrameError never leaves the receiver: it is the reason the decoder
//    dropped a frame, counted per reason for the STATUS heartbeat.

#include <cstdint>

namespace nlsoft::protocol {

// Values 0..8 and 10 are the same as shared/status.hpp's nlsoft::Status, so the
// firmware forwards a controller or model-loader verdict with a cast.
enum class StatusCode : uint8_t {
  Ok = 0,
  OutOfRange = 1,     // value outside [min, max], or outside the object
  NotFinite = 2,      // NaN or infinity where a finite float is required
  WrongSize = 3,      // vector has the wrong element count
  UnknownId = 4,      // parameter id, reference id, transfer kind, list index
  Inconsistent = 5,   // valid alone, invalid with the rest (Nc > N, u_min >= u_max)
  TooLarge = 6,       // exceeds a capacity (transfer size, horizon)
  BadFormat = 7,      // transferred object arrived intact but failed validation
  BadChecksum = 8,    // transferred object's CRC-32 does not match XFER_BEGIN
  BadLength = 9,      // payload length breaks the type's rule
  Unsupported = 10,   // request type or option known but not implemented here
  ReadOnly = 11,
  WrongState = 12,    // not allowed in the current run state
  Busy = 13,          // resource in use (e.g. another transfer is open)
  XferNotOpen = 14,
  XferIncomplete = 15,
  Internal = 16,
};

constexpr const char* to_string(StatusCode s) {
  switch (s) {
    case StatusCode::Ok: return "ok";
    case StatusCode::OutOfRange: return "out_of_range";
    case StatusCode::NotFinite: return "not_finite";
    case StatusCode::WrongSize: return "wrong_size";
    case StatusCode::UnknownId: return "unknown_id";
    case StatusCode::Inconsistent: return "inconsistent";
    case StatusCode::TooLarge: return "too_large";
    case StatusCode::BadFormat: return "bad_format";
    case StatusCode::BadChecksum: return "bad_checksum";
    case StatusCode::BadLength: return "bad_length";
    case StatusCode::Unsupported: return "unsupported";
    case StatusCode::ReadOnly: return "read_only";
    case StatusCode::WrongState: return "wrong_state";
    case StatusCode::Busy: return "busy";
    case StatusCode::XferNotOpen: return "xfer_not_open";
    case StatusCode::XferIncomplete: return "xfer_incomplete";
    case StatusCode::Internal: return "internal";
  }
  return "unknown_status";
}

// Order is the order of the decoder's checks (PROTOCOL.md, "Receiving"), so a
// frame with several faults always reports the same one on every peer.
enum class FrameError : uint8_t {
  None = 0,
  Oversize = 1,        // decodes to more than kMaxRawFrame bytes
  CobsError = 2,       // delimiter arrived inside a COBS block
  WrongVersion = 3,    // byte 0 is not kProtocolVersion
  Truncated = 4,       // fewer bytes than header + CRC, or than the header declares
  LengthMismatch = 5,  // more bytes than the header declares
  UnknownType = 6,
  BadCrc = 7,
  BadLength = 8,       // payload length not valid for the message type
};

constexpr unsigned kFrameErrorCount = 9;

constexpr const char* to_string(FrameError e) {
  switch (e) {
    case FrameError::None: return "none";
    case FrameError::Oversize: return "oversize";
    case FrameError::CobsError: return "cobs_error";
    case FrameError::Truncated: return "truncated";
    case FrameError::LengthMismatch: return "length_mismatch";
    case FrameError::WrongVersion: return "wrong_version";
    case FrameError::UnknownType: return "unknown_type";
    case FrameError::BadCrc: return "bad_crc";
    case FrameError::BadLength: return "bad_length";
  }
  return "unknown_error";
}

}  // namespace nlsoft::protocol
