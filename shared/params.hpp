#pragma once
// The parameter table: everything tunable, described once. The firmware
// validates every write against it and the console builds its editor from the
// list the firmware sends, so neither side hard-codes a parameter.
#include <cstdint>
#include <cstring>

#include "shared/capacity.hpp"
#include "shared/status.hpp"

namespace nlsoft {

enum class ParamId : uint8_t {
  Q = 0,       // output weights, diag(Q)            eq. 2, term 1
  Lambda,      // input-change weights, diag(Lambda) eq. 2, term 2
  S,           // barrier scale s                    eq. 2, term 3
  B,           // barrier centre b
  R,           // barrier range r
  N,           // prediction horizon
  N1,          // first step counted in the cost (N2 = N)
  Nc,          // control horizon
  Eps,         // finite-difference step (fd mode)
  UMin,        // input lower limits
  UMax,        // input upper limits
  NrTol,       // Newton-Raphson tolerance on max |dU|
  NrMaxIter,   // Newton-Raphson iteration cap
  Mode,        // derivative mode: 0 exact, 1 fd
  Feedback,    // y-queue source: 0 own prediction (paper), 1 measured output
  Count
};

enum class ParamType : uint8_t { F32 = 0, U8 = 1, Enum = 2 };
enum class ParamSize : uint8_t { Scalar = 0, PerOutput = 1, PerInput = 2 };

struct ParamDesc {
  ParamId id;
  const char* name;
  const char* unit;
  ParamType type;
  ParamSize size;
  float min, max;
  const char* meaning;
};

// Bounds are the widest values the solver stays finite with; a platform may
// tighten the input limits further. Ordered by ParamId.
inline constexpr ParamDesc kParamTable[] = {
    {ParamId::Q, "Q", "1/y^2", ParamType::F32, ParamSize::PerOutput, 0.0f, 1e12f,
     "tracking weight per output, diagonal of Q"},
    {ParamId::Lambda, "Lambda", "1/u^2", ParamType::F32, ParamSize::PerInput, 0.0f, 1e12f,
     "weight on input changes per actuator, diagonal of Lambda"},
    {ParamId::S, "s", "", ParamType::F32, ParamSize::Scalar, 0.0f, 1e3f,
     "barrier scale (Soloway); tiny keeps it a soft wall"},
    {ParamId::B, "b", "u", ParamType::F32, ParamSize::Scalar, -1e6f, 1e6f,
     "barrier centre"},
    {ParamId::R, "r", "u", ParamType::F32, ParamSize::Scalar, 1e-6f, 1e7f,
     "barrier range: the wall sits at b +- r/2"},
    {ParamId::N, "N", "steps", ParamType::U8, ParamSize::Scalar, 1.0f, 255.0f,
     "prediction horizon"},
    {ParamId::N1, "N1", "steps", ParamType::U8, ParamSize::Scalar, 1.0f, 255.0f,
     "first predicted step in the cost"},
    {ParamId::Nc, "Nc", "steps", ParamType::U8, ParamSize::Scalar, 1.0f, 255.0f,
     "control horizon, <= N"},
    {ParamId::Eps, "eps", "u", ParamType::F32, ParamSize::Scalar, 1e-7f, 1e3f,
     "finite-difference step (fd mode)"},
    {ParamId::UMin, "u_min", "u", ParamType::F32, ParamSize::PerInput, -1e6f, 1e6f,
     "lower input limit per actuator"},
    {ParamId::UMax, "u_max", "u", ParamType::F32, ParamSize::PerInput, -1e6f, 1e6f,
     "upper input limit per actuator"},
    {ParamId::NrTol, "nr_tol", "u", ParamType::F32, ParamSize::Scalar, 0.0f, 1e3f,
     "stop when max |dU| falls below this"},
    {ParamId::NrMaxIter, "nr_max_iter", "", ParamType::U8, ParamSize::Scalar, 1.0f, 20.0f,
     "Newton-Raphson iteration cap per control step"},
    {ParamId::Mode, "mode", "", ParamType::Enum, ParamSize::Scalar, 0.0f, 1.0f,
     "derivatives: 0 exact (chain rule), 1 fd (central differences)"},
    {ParamId::Feedback, "feedback", "", ParamType::Enum, ParamSize::Scalar, 0.0f, 1.0f,
     "y history from: 0 own predictions (paper), 1 measured output"},
};
static_assert(sizeof(kParamTable) / sizeof(kParamTable[0]) == size_t(ParamId::Count),
              "one descriptor per ParamId, in order");

inline const ParamDesc* find_param(const char* name) {
  for (const ParamDesc& d : kParamTable)
    if (std::strcmp(d.name, name) == 0) return &d;
  return nullptr;
}

inline int param_count(const ParamDesc& d, int m, int n) {
  return d.size == ParamSize::PerOutput ? n : (d.size == ParamSize::PerInput ? m : 1);
}

// How dJ/dU and d2J/dU2 are obtained (derivatives.hpp).
enum class DerivMode : uint8_t { Exact = 0, Fd = 1 };

enum class Feedback : uint8_t { Predicted = 0, Measured = 1 };

template <class Cap>
struct Params {
  float Q[Cap::n] = {};
  float Lambda[Cap::m] = {};
  float s = 0.0f, b = 0.0f, r = 1.0f;
  uint8_t N = 1, N1 = 1, Nc = 1;
  float eps = 1e-3f;
  float u_min[Cap::m] = {};
  float u_max[Cap::m] = {};
  float nr_tol = 1e-4f;
  uint8_t nr_max_iter = 3;
  DerivMode mode = DerivMode::Exact;
  Feedback feedback = Feedback::Predicted;
};

// Where a rejected write failed: the status and the offending element.
struct ParamResult {
  Status status;
  int16_t index;  // element index, -1 when the whole value is at fault
};

// Cross-parameter rules, checked on the candidate set before anything changes.
template <class Cap>
ParamResult check_consistent(const Params<Cap>& P, int m) {
  if (P.N > Cap::N) return {Status::TooLarge, -1};
  if (P.Nc > Cap::Nc) return {Status::TooLarge, -1};
  if (P.Nc > P.N || P.N1 > P.N) return {Status::Inconsistent, -1};
  for (int i = 0; i < m; ++i)
    if (!(P.u_min[i] < P.u_max[i])) return {Status::Inconsistent, int16_t(i)};
  return {Status::Ok, -1};
}

// Reads the current value(s) of a parameter as floats. Returns the count.
template <class Cap>
int get_param(const Params<Cap>& P, ParamId id, int m, int n, float* out) {
  auto copy = [&](const float* src, int c) {
    for (int i = 0; i < c; ++i) out[i] = src[i];
    return c;
  };
  switch (id) {
    case ParamId::Q: return copy(P.Q, n);
    case ParamId::Lambda: return copy(P.Lambda, m);
    case ParamId::S: out[0] = P.s; return 1;
    case ParamId::B: out[0] = P.b; return 1;
    case ParamId::R: out[0] = P.r; return 1;
    case ParamId::N: out[0] = P.N; return 1;
    case ParamId::N1: out[0] = P.N1; return 1;
    case ParamId::Nc: out[0] = P.Nc; return 1;
    case ParamId::Eps: out[0] = P.eps; return 1;
    case ParamId::UMin: return copy(P.u_min, m);
    case ParamId::UMax: return copy(P.u_max, m);
    case ParamId::NrTol: out[0] = P.nr_tol; return 1;
    case ParamId::NrMaxIter: out[0] = P.nr_max_iter; return 1;
    case ParamId::Mode: out[0] = float(uint8_t(P.mode)); return 1;
    case ParamId::Feedback: out[0] = float(uint8_t(P.feedback)); return 1;
    case ParamId::Count: break;
  }
  return 0;
}

// Validates every element and the resulting set, then applies all of it or
// nothing: a refused write leaves P exactly as it was.
template <class Cap>
ParamResult set_param(Params<Cap>& P, ParamId id, const float* v, int count, int m, int n) {
  if (uint8_t(id) >= uint8_t(ParamId::Count)) return {Status::UnknownId, -1};
  const ParamDesc& d = kParamTable[uint8_t(id)];
  if (count != param_count(d, m, n)) return {Status::WrongSize, -1};
  for (int i = 0; i < count; ++i) {
    if (!(v[i] - v[i] == 0.0f)) return {Status::NotFinite, int16_t(i)};
    if (v[i] < d.min || v[i] > d.max) return {Status::OutOfRange, int16_t(i)};
    if (d.type != ParamType::F32 && v[i] != float(int(v[i]))) return {Status::OutOfRange, int16_t(i)};
  }
  Params<Cap> c = P;
  auto copy = [&](float* dst) {
    for (int i = 0; i < count; ++i) dst[i] = v[i];
  };
  switch (id) {
    case ParamId::Q: copy(c.Q); break;
    case ParamId::Lambda: copy(c.Lambda); break;
    case ParamId::S: c.s = v[0]; break;
    case ParamId::B: c.b = v[0]; break;
    case ParamId::R: c.r = v[0]; break;
    case ParamId::N: c.N = uint8_t(v[0]); break;
    case ParamId::N1: c.N1 = uint8_t(v[0]); break;
    case ParamId::Nc: c.Nc = uint8_t(v[0]); break;
    case ParamId::Eps: c.eps = v[0]; break;
    case ParamId::UMin: copy(c.u_min); break;
    case ParamId::UMax: copy(c.u_max); break;
    case ParamId::NrTol: c.nr_tol = v[0]; break;
    case ParamId::NrMaxIter: c.nr_max_iter = uint8_t(v[0]); break;
    case ParamId::Mode: c.mode = DerivMode(uint8_t(v[0])); break;
    case ParamId::Feedback: c.feedback = Feedback(uint8_t(v[0])); break;
    case ParamId::Count: return {Status::UnknownId, -1};
  }
  const ParamResult ok = check_consistent(c, m);
  if (ok.status != Status::Ok) return ok;
  P = c;
  return {Status::Ok, -1};
}

}  // namespace nlsoft
