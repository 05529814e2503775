#pragma once
// The reference in force: built-in parameters (REF_SELECT) and the uploaded
// table of points (transfer kind 1). A table upload replaces the old table
// only once it is complete, CRC-checked and valid (PROTOCOL.md 9.4).
#include <cmath>
#include <cstring>

#include "protocol/status.hpp"
#include "shared/reference.hpp"

namespace nlsoft::fw {

namespace proto = nlsoft::protocol;

class ReferenceSlot {
 public:
  // points: caller-owned storage for the active table, capacity in floats.
  ReferenceSlot(float* points, uint32_t capacity) : points_(points), cap_(capacity) {
    ref_.kind = RefKind::Hold;
    ref_.hold = 1;
  }

  void set_hold_at(const float* y, int n) {
    ref_ = RefParams{};
    ref_.kind = RefKind::Hold;
    for (int i = 0; i < n && i < 3; ++i) ref_.c[i] = y[i];
    k_ = 0;
  }

  proto::StatusCode select(const RefParams& p) {
    if (p.kind == RefKind::Table && count_ == 0) return proto::StatusCode::WrongState;
    const ReferenceTable t = table();
    if (reference_check(p, count_ ? &t : nullptr) != nullptr) return proto::StatusCode::OutOfRange;
    ref_ = p;
    k_ = 0;  // restarts at the next control step
    return proto::StatusCode::Ok;
  }

  // Table object: format u8 = 1, n u8, reserved u16, count u32, f32[count][n].
  proto::StatusCode commit_table(const uint8_t* obj, uint32_t size, int n) {
    if (size < 8 || obj[0] != 1) return proto::StatusCode::BadFormat;
    if (obj[1] != n) return proto::StatusCode::Inconsistent;
    uint32_t count;
    std::memcpy(&count, obj + 4, 4);
    if (count == 0 || size != 8 + 4u * uint32_t(n) * count) return proto::StatusCode::BadFormat;
    if (count * uint32_t(n) > cap_) return proto::StatusCode::TooLarge;
    for (uint32_t i = 0; i < count * uint32_t(n); ++i) {
      float v;
      std::memcpy(&v, obj + 8 + 4 * i, 4);
      if (!std::isfinite(v)) return proto::StatusCode::BadFormat;
    }
    std::memcpy(points_, obj + 8, 4u * count * uint32_t(n));
    count_ = count;
    n_ = uint8_t(n);
    return proto::StatusCode::Ok;
  }

  // Rows y_ref(k+1) ... y_ref(k+rows) of the running reference.
  void rows(float* out, int rows, int n) const {
    const ReferenceTable t = table();
    for (int j = 0; j < rows; ++j) reference_at(ref_, count_ ? &t : nullptr, k_ + 1 + uint32_t(j), out + j * n, n);
  }
  void advance() { ++k_; }
  void restart() { k_ = 0; }
  uint8_t id() const { return uint8_t(ref_.kind); }
  uint32_t table_points() const { return count_; }
  uint32_t table_capacity_floats() const { return cap_; }

 private:
  ReferenceTable table() const { return ReferenceTable{points_, count_, n_}; }
  float* points_;
  uint32_t cap_;
  uint32_t count_ = 0;
  uint8_t n_ = 0;
  RefParams ref_{};
  uint32_t k_ = 0;
};

}  // namespace nlsoft::fw
