#pragma once
// The rig as a firmware holds it: a rig file's values (docs/rig-file.md) as
// plain data, so the firmware core serves any rig without a switch over rig
// names. An image gets it as a constexpr object from the header generated
// for its rig (`nlsoft-console firmware build --rig`); the simulator fills
// one from the rig file it is started with.
//
// The capacities are the rig file's (what the loader admits); an image's
// controller capacity (shared/capacity.hpp) may be smaller, and
// rig_params() says TooLarge when the rig does not fit it.
#include <cstdint>

#include "shared/firmware_features.hpp"
#include "shared/params.hpp"
#include "shared/platform_id.hpp"
#include "shared/reference.hpp"
#include "shared/status.hpp"

namespace nlsoft {

constexpr int kRigMaxM = 8;   // actuators (paper: m)
constexpr int kRigMaxN = 6;   // controlled outputs (paper: n)
constexpr int kRigMaxW = 32;  // sensor channels, extra network inputs (paper: w)
constexpr int kRigMaxNameLen = 24;

struct RigConfig {
  const char* name;     // the rig file's `name`
  uint32_t hash;        // CRC-32 of the rig file's text; 0 when not built from a file
  PlatformId platform;  // INFO's platform byte: a shipped rig's number, or Custom
  uint8_t m, n, w, nd, dd;
  float rate_hz;
  float u_min[kRigMaxM], u_max[kRigMaxM], u_neutral[kRigMaxM];
  // The controller's defaults, eq. 2's weights and the solver's settings.
  float Q[kRigMaxN], Lambda[kRigMaxM];
  float s, b, r, eps, nr_tol;
  uint8_t N, N1, Nc, nr_max_iter;
  DerivMode mode;
  Feedback feedback;
  RefParams reference;  // the task a run follows until the console selects one
  // The services beyond the minimum the rig file asks for ([firmware]
  // features, shared/firmware_features.hpp); a firmware serves those it
  // was built with among them.
  uint32_t features = kAllFirmwareFeatures;
};

// The rig's defaults as the parameter set the controller runs. Fails
// (TooLarge) when the capacity cannot hold the rig.
template <class Cap>
Status rig_params(const RigConfig& rig, Params<Cap>& out) {
  if (rig.m > Cap::m || rig.n > Cap::n || rig.w > Cap::w || rig.N > Cap::N || rig.Nc > Cap::Nc)
    return Status::TooLarge;
  Params<Cap> P;
  for (int i = 0; i < rig.n; ++i) P.Q[i] = rig.Q[i];
  for (int i = 0; i < rig.m; ++i) {
    P.Lambda[i] = rig.Lambda[i];
    P.u_min[i] = rig.u_min[i];
    P.u_max[i] = rig.u_max[i];
  }
  P.s = rig.s;
  P.b = rig.b;
  P.r = rig.r;
  P.eps = rig.eps;
  P.N = rig.N;
  P.N1 = rig.N1;
  P.Nc = rig.Nc;
  P.nr_tol = rig.nr_tol;
  P.nr_max_iter = rig.nr_max_iter;
  P.mode = rig.mode;
  P.feedback = rig.feedback;
  out = P;
  return Status::Ok;
}

}  // namespace nlsoft
