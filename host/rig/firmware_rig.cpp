#include "host/rig/firmware_rig.hpp"

#include "host/rig/rig_reference.hpp"

namespace nlsoft::host {

RigConfig firmware_rig(const Rig& rig) {
  RigConfig c{};
  c.name = rig.name.c_str();
  c.hash = rig.hash;
  c.platform = PlatformId(rig.info_platform);
  c.m = uint8_t(rig.m()), c.n = uint8_t(rig.n()), c.w = uint8_t(rig.w());
  c.nd = uint8_t(rig.nd), c.dd = uint8_t(rig.dd);
  c.rate_hz = float(rig.rate_hz);
  const RigController& k = rig.controller;
  for (int i = 0; i < rig.m() && i < kRigMaxM; ++i) {
    const RigInput& in = rig.inputs[size_t(i)];
    c.u_min[i] = float(in.min);
    c.u_max[i] = float(in.max);
    c.u_neutral[i] = float(in.neutral);
    c.Lambda[i] = float(k.Lambda[size_t(i)]);
  }
  for (int i = 0; i < rig.n() && i < kRigMaxN; ++i) c.Q[i] = float(k.Q[size_t(i)]);
  c.s = float(k.s), c.b = float(k.b), c.r = float(k.r), c.eps = float(k.eps), c.nr_tol = float(k.nr_tol);
  c.N = uint8_t(k.N), c.N1 = uint8_t(k.N1), c.Nc = uint8_t(k.Nc), c.nr_max_iter = uint8_t(k.nr_max_iter);
  c.mode = k.mode;
  c.feedback = k.feedback;
  c.reference = rig_reference(rig, rig.reference.kind);
  c.features = rig.firmware_features;
  return c;
}

}  // namespace nlsoft::host
