#pragma once
// The reference in force: built-in parameters (REF_SELECT) and the uploaded
// table of points (transfer kind 1). A table upload replaces the old table
// only once it is complete, CRC-checked and valid (PROTOCOL.md 9.4).
#include <cmath>
#include <cstring>

#include "protocol/messages.hpp"
#include "protocol/status.hpp"
#include "shared/reference.hpp"

namespace nlsoft::fw {

namespace proto = nlsoft::protocol;

// A refused REF_SELECT as NACK reports it.
struct RefRefusal {
  proto::StatusCode status = proto::StatusCode::Ok;
  uint8_t field = proto::kNoField, element = proto::kNoField;
};

// REF_SELECT's field numbers (PROTOCOL.md section 7) and the fields each
// reference reads. The others are ignored whatever they hold, NaN included,
// and cleared before the reference runs, so no unused value is ever read.
namespace ref_field {
constexpr uint8_t kRefId = 0, kLevelCount = 1, kHold = 2, kA = 3, kB = 4, kC = 5, kCenter = 6, kOmega = 7,
                  kLambda = 8, kScale = 9, kLevels = 10;
constexpr uint16_t bit(uint8_t f) { return uint16_t(1u << f); }
constexpr uint16_t used(RefKind k) {
  switch (k) {
    case RefKind::Infinity: return bit(kA) | bit(kB) | bit(kC) | bit(kCenter) | bit(kOmega);
    case RefKind::Pringle:
    case RefKind::Diagonal: return bit(kA) | bit(kB) | bit(kC) | bit(kCenter) | bit(kLambda);
    case RefKind::Swirl: return bit(kHold) | bit(kCenter) | bit(kScale);
    case RefKind::Step: return bit(kLevelCount) | bit(kHold) | bit(kCenter) | bit(kLevels);
    case RefKind::Table: return bit(kHold);
    case RefKind::Hold: return bit(kCenter);
  }
  return 0;
}
}  // namespace ref_field

// Checks a REF_SELECT field by field in wire order and reports the first
// failure; on success `out` holds the used fields and zeros elsewhere.
inline RefRefusal check_ref_select(const proto::RefSelect& m, RefParams& out) {
  namespace f = ref_field;
  RefRefusal r;
  auto refuse = [&r](proto::StatusCode s, uint8_t field, uint8_t element) {
    r.status = s, r.field = field, r.element = element;
    return r;
  };
  if (m.ref_id >= kRefKindCount) return refuse(proto::StatusCode::UnknownId, f::kRefId, proto::kNoField);
  const RefKind kind = RefKind(m.ref_id);
  const uint16_t used = f::used(kind);
  auto finite = [](float x) { return x - x == 0.0f; };
  RefParams p{};
  p.kind = kind;
  if (used & f::bit(f::kLevelCount)) {
    if (m.level_count < 1 || m.level_count > kRefMaxLevels)
      return refuse(proto::StatusCode::OutOfRange, f::kLevelCount, proto::kNoField);
    p.level_count = m.level_count;
  }
  if (used & f::bit(f::kHold)) p.hold = m.hold;
  const float* scalars[] = {&m.a, &m.b, &m.c};
  float* dest[] = {&p.A, &p.B, &p.C};
  for (uint8_t i = 0; i < 3; ++i) {
    if (!(used & f::bit(uint8_t(f::kA + i)))) continue;
    if (!finite(*scalars[i])) return refuse(proto::StatusCode::NotFinite, uint8_t(f::kA + i), proto::kNoField);
    *dest[i] = *scalars[i];
  }
  if (used & f::bit(f::kCenter)) {
    for (uint8_t i = 0; i < 3; ++i) {
      if (!finite(m.center[i])) return refuse(proto::StatusCode::NotFinite, f::kCenter, i);
      p.c[i] = m.center[i];
    }
  }
  if (used & f::bit(f::kOmega)) {
    if (!finite(m.omega)) return refuse(proto::StatusCode::NotFinite, f::kOmega, proto::kNoField);
    p.omega = m.omega;
  }
  if (used & f::bit(f::kLambda)) {
    if (!finite(m.lambda)) return refuse(proto::StatusCode::NotFinite, f::kLambda, proto::kNoField);
    if (!(m.lambda > 0.0f)) return refuse(proto::StatusCode::OutOfRange, f::kLambda, proto::kNoField);
    p.lambda = m.lambda;
  }
  if (used & f::bit(f::kScale)) {
    if (!finite(m.scale)) return refuse(proto::StatusCode::NotFinite, f::kScale, proto::kNoField);
    p.scale = m.scale;
  }
  if (used & f::bit(f::kLevels)) {
    // Only the levels in use: level_count says how many.
    for (uint8_t i = 0; i < p.level_count; ++i) {
      if (!finite(m.levels[i])) return refuse(proto::StatusCode::NotFinite, f::kLevels, i);
      p.levels[i] = m.levels[i];
    }
  }
  // The saddle divides by B and C whenever A is non-zero.
  if ((kind == RefKind::Pringle || kind == RefKind::Diagonal) && p.A != 0.0f) {
    if (p.B == 0.0f) return refuse(proto::StatusCode::Inconsistent, f::kB, proto::kNoField);
    if (p.C == 0.0f) return refuse(proto::StatusCode::Inconsistent, f::kC, proto::kNoField);
  }
  out = p;
  return r;
}

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

  // REF_SELECT: all of it or nothing, the refusal naming the field.
  RefRefusal select(const proto::RefSelect& m) {
    RefParams p;
    RefRefusal r = check_ref_select(m, p);
    if (r.status != proto::StatusCode::Ok) return r;
    if (p.kind == RefKind::Table && count_ == 0) {
      r.status = proto::StatusCode::WrongState, r.field = ref_field::kRefId;
      return r;
    }
    const proto::StatusCode s = select(p);
    if (s != proto::StatusCode::Ok) r.status = s;  // check_ref_select covers reference_check's rules
    return r;
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
