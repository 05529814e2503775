#pragma once
// A rig's controller defaults as the parameter set the controller runs
// (Params<Cap>, shared/params.hpp).
#include "host/rig/rig.hpp"
#include "shared/params.hpp"

namespace nlsoft::host {

// Fails (TooLarge) when the capacity cannot hold the rig; the loader has
// already put every value through PARAM_SET's checks.
template <class Cap>
Status rig_params(const Rig& rig, Params<Cap>& out) {
  const RigController& c = rig.controller;
  if (rig.m() > Cap::m || rig.n() > Cap::n || c.N > Cap::N || c.Nc > Cap::Nc) return Status::TooLarge;
  Params<Cap> P;
  for (int i = 0; i < rig.n(); ++i) P.Q[i] = float(c.Q[size_t(i)]);
  for (int i = 0; i < rig.m(); ++i) {
    P.Lambda[i] = float(c.Lambda[size_t(i)]);
    P.u_min[i] = float(rig.inputs[size_t(i)].min);
    P.u_max[i] = float(rig.inputs[size_t(i)].max);
  }
  P.s = float(c.s);
  P.b = float(c.b);
  P.r = float(c.r);
  P.eps = float(c.eps);
  P.N = uint8_t(c.N);
  P.N1 = uint8_t(c.N1);
  P.Nc = uint8_t(c.Nc);
  P.nr_tol = float(c.nr_tol);
  P.nr_max_iter = uint8_t(c.nr_max_iter);
  P.mode = c.mode;
  P.feedback = c.feedback;
  out = P;
  return Status::Ok;
}

}  // namespace nlsoft::host
