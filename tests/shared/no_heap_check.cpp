// Runs one control step of a controller of each shipped rig's size. Built with the
// embedded flags and, in CMake, linked with every allocation function
// wrapped away: it links only if nothing reachable allocates.
#include "shared/controller.hpp"
#include "shared/excitation.hpp"
#include "shared/plant_generic.hpp"
#include "../support/rig_capacities.hpp"

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
    const LayerKind kinds[] = {First::kind, Rest::kind...};
    int in = Mo.p();
    Mo.layer_count = uint8_t(1 + sizeof...(Rest));
    for (int l = 0; l < Mo.layer_count; ++l) {
      Mo.layer[l] = Layer{kinds[l], Activation::Tanh, Activation::HardSigmoid, true,
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

// A rig as large as the capacity (these capacities are tight fits: their
// m, n, w, nd are a rig's), with plain parameters: enough to make every
// path of the step reachable.
template <class Cap>
int run_one(float* params, unsigned count) {
  using namespace nlsoft;
  Model<Cap> M;
  M.m = Cap::m;
  M.n = Cap::n;
  M.w = Cap::w;
  M.nd = Cap::nd;
  M.dd = Cap::nd;
  ShapeLayers<Cap, typename First<typename Cap::Shapes>::type>::fill(M);
  M.param_count = M.norm_count();
  for (int l = 0; l < M.layer_count; ++l) M.param_count += layer_weight_count(M.layer[l]);
  if (M.param_count > count) return 1;
  for (unsigned i = 0; i < M.param_count; ++i) params[i] = 0.01f * float(i % 7);
  M.params = params;
  if (finalize_model(M) != Status::Ok) return 2;
  static Controller<Cap> ctl;
  Params<Cap> P;
  for (int i = 0; i < Cap::n; ++i) P.Q[i] = 1.0f;
  for (int i = 0; i < Cap::m; ++i) P.Lambda[i] = 1.0f, P.u_min[i] = -1.0f, P.u_max[i] = 1.0f;
  P.N = uint8_t(Cap::N < 8 ? Cap::N : 8);
  P.Nc = uint8_t(Cap::Nc);
  P.nr_max_iter = 1;
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

// A generic plant from a constexpr spec, as a HIL image embeds one: it must
// build for the MCU and step without a heap.
constexpr nlsoft::GenericPlantSpec kGenericSpec = [] {
  nlsoft::GenericPlantSpec s{};
  s.m = 2, s.n = 2, s.w = 3;
  s.dt = 0.01f;
  s.input[0] = {0.0f, 1.0f, 0.5f, 2.0f, nlsoft::GenericShape::Tanh, 0.3f, 1.0f, 0.02f, 0.05f};
  s.input[1] = {-1.0f, 1.0f, 0.0f, 1.0f, nlsoft::GenericShape::Power, 1.0f, 1.5f, 0.0f, 0.0f};
  s.output[0] = {-5.0f, 5.0f, 0.0f, 0.02f};
  s.output[1] = {-5.0f, 5.0f, 1.0f, 0.0f};
  s.B[0][0] = 1.0f, s.B[1][1] = 1.0f;
  s.C[0][0] = 1.0f, s.C[1][2] = 1.0f, s.C[2][3] = 1.0f;
  s.sensor[0].noise = 0.01f;
  return s;
}();

int run_generic() {
  if (nlsoft::generic_spec_problem(kGenericSpec) != nullptr) return 1;
  static nlsoft::GenericPlant plant(kGenericSpec, 1);
  float u[2] = {0.9f, -0.4f}, y[2], l[3];
  plant.step(u, kGenericSpec.dt);
  plant.output(y);
  plant.sensors(l);
  // ... and as a HIL image holds it: the spec in flash, the state alone in RAM.
  static nlsoft::FixedGenericPlant<kGenericSpec> fixed;
  fixed.reset(1);
  fixed.step(u, kGenericSpec.dt);
  float yf[2];
  fixed.output(yf);
  return y[0] - y[0] == 0.0f && l[0] - l[0] == 0.0f && yf[0] == y[0] ? 0 : 2;
}

}  // namespace

// Every excitation signal, a few steps each, with one stream per input and
// mixed (where the signal has a mixed form).
int run_excitation() {
  using namespace nlsoft;
  const float lo[2] = {0.0f, -1.0f}, hi[2] = {1.0f, 1.0f}, mid[2] = {0.0f, 0.0f};
  int bad = 0;
  for (uint8_t k = 0; k < 2 * kExcitationSignalCount; ++k) {
    ExcitationSpec s;
    s.signal = ExcitationSignal(k % kExcitationSignalCount);
    s.mixed = k >= kExcitationSignalCount;
    if (s.mixed && s.signal == ExcitationSignal::Prbs) continue;
    s.duration = 100;
    static Excitation e;
    if (e.configure(s, 100.0f, lo, hi, mid, 2).status != Status::Ok) return 1;
    float u[2];
    while (!e.done()) {
      e.next(u);
      bad += !(u[0] >= lo[0] && u[0] <= hi[0]);
    }
  }
  return bad != 0;
}

int main() {
  using namespace nlsoft;
  int rc = run_one<HaselCapacity>(storage, 600);
  rc |= run_one<TendonCapacity>(storage, 600) << 3;
  rc |= run_one<MsdCapacity>(storage, 600) << 6;
  rc |= run_generic() << 9;
  rc |= run_excitation() << 10;
  return rc;
}
