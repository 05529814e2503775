// Runs one control step of each preset-sized controller. Built with the
// embedded flags and, in CMake, linked with every allocation function
// wrapped away: it links only if nothing reachable allocates.
#include "shared/controller.hpp"
#include "shared/platform.hpp"

namespace {

// A tiny two-layer model, enough to make the code reachable.
template <class Cap>
int run_one(nlsoft::PlatformId id, float* params, unsigned count) {
  using namespace nlsoft;
  const Preset& pr = preset(id);
  Model<Cap> M;
  M.m = pr.m;
  M.n = pr.n;
  M.w = pr.w;
  M.nd = pr.nd;
  M.dd = pr.dd;
  M.layer_count = 2;
  M.layer[0] = Layer{LayerKind::Gru, Activation::Tanh, Activation::HardSigmoid, true, uint16_t(M.p()), 2, 0};
  M.layer[1] = Layer{LayerKind::Dense, Activation::Tanh, Activation::Linear, false, 2, pr.n, 0};
  M.param_count = M.norm_count() + layer_weight_count(M.layer[0]) + layer_weight_count(M.layer[1]);
  if (M.param_count > count) return 1;
  for (unsigned i = 0; i < M.param_count; ++i) params[i] = 0.01f * float(i % 7);
  M.params = params;
  if (finalize_model(M) != Status::Ok) return 2;
  static Controller<Cap> ctl;
  Params<Cap> P;
  if (preset_params(pr, P) != Status::Ok) return 3;
  if (ctl.configure(&M, P) != Status::Ok) return 4;
  float u0[Cap::m] = {}, y0[Cap::n] = {}, l0[Cap::w + 1] = {}, ref[Cap::N * Cap::n] = {};
  ctl.reset(u0, y0, l0);
  const StepResult<Cap> r = ctl.step(ref, l0, y0);
  return r.u[0] - r.u[0] == 0.0f ? 0 : 5;
}

float storage[600];

}  // namespace

int main() {
  using namespace nlsoft;
  int rc = run_one<HaselCapacity>(PlatformId::Hasel, storage, 600);
  rc |= run_one<TendonCapacity>(PlatformId::Tendon, storage, 600) << 3;
  rc |= run_one<MsdCapacity>(PlatformId::Msd, storage, 600) << 6;
  return rc;
}
