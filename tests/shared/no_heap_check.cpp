// Runs one control step of each preset-sized controller. Built with the
// embedded flags and, in CMake, linked with every allocation function
// wrapped away: it links only if nothing reachable allocates.
#include "shared/controller.hpp"
#include "shared/platform.hpp"

namespace {

// A model of the first shape the capacity has kernels for, with small
// weights: enough to make the code reachable.
template <class Cap, class S>
struct ShapeLayers;
template <class Cap, int M, int N, int W, int ND, class First, class... Rest>
struct ShapeLayers<Cap, nlsoft::NetShape<M, N, W, ND, First, Rest...>> {
  static void fill(nlsoft::Model<Cap>& Mo) {
    using namespace nlsoft;
    const int units[] = {First::units, Rest::units...};
    const bool gru[] = {First::gru, Rest::gru...};
    int in = Mo.p();
    Mo.layer_count = uint8_t(1 + sizeof...(Rest));
    for (int l = 0; l < Mo.layer_count; ++l) {
      Mo.layer[l] = Layer{gru[l] ? LayerKind::Gru : LayerKind::Dense, Activation::Tanh, Activation::HardSigmoid, true,
                          uint16_t(in), uint16_t(units[l]), 0};
      in = units[l];
    }
  }
};
template <class List>
struct First;
template <class S, class... More>
struct First<nlsoft::ShapeList<S, More...>> {
  using type = S;
};

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
  ShapeLayers<Cap, typename First<typename Cap::Shapes>::type>::fill(M);
  M.param_count = M.norm_count();
  for (int l = 0; l < M.layer_count; ++l) M.param_count += layer_weight_count(M.layer[l]);
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
  const DerivMode modes[] = {DerivMode::Exact, DerivMode::Fd};
  for (DerivMode mode : modes) {
    P.mode = mode;
    if (ctl.configure(&M, P) != Status::Ok) return 4;
    const StepResult<Cap> r = ctl.step(ref, l0, y0);
    if (!(r.u[0] - r.u[0] == 0.0f)) return 5;
  }
  return 0;
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
