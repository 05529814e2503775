// One control step (Newton-Raphson + horizon + clamp) on the paper's model
// shapes, exact and fd derivatives. Reports wall time per step and the heap
// allocations made by the step itself (counted by a replaced operator new;
// the controller must make none).
//
//   build/tests/bench/nlsoft-bench-controller
#include <benchmark/benchmark.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

#include "shared/controller.hpp"
#include <fstream>
#include <iterator>
#include <string>
#include "shared/model_file.hpp"
#include "shared/platform.hpp"

namespace {

std::atomic<long> g_allocations{0};

}  // namespace

void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace {

using namespace nlsoft;

// The shipped model of the platform (app/models), or, if it is missing, the
// paper's architecture with seeded random weights: the cost of a step depends
// on the shapes and on the iteration count, which the benchmark reports.
template <class Cap>
struct Rig {
  Model<Cap> model;
  std::vector<float> params, shipped_params;
  Controller<Cap> ctl;
  std::vector<float> sensors, ref;

  Rig(PlatformId id, DerivMode mode) {
    const Preset& pr = preset(id);
    model.m = pr.m, model.n = pr.n, model.w = pr.w, model.nd = pr.nd, model.dd = pr.dd;
    const uint16_t p = uint16_t(model.p());
    if (id == PlatformId::Hasel) {  // Dense 36 -> 5 relu -> 5 relu -> 3 tanh
      model.layer_count = 3;
      model.layer[0] = Layer{LayerKind::Dense, Activation::Relu, Activation::Sigmoid, false, p, 5, 0};
      model.layer[1] = Layer{LayerKind::Dense, Activation::Relu, Activation::Sigmoid, false, 5, 5, 0};
      model.layer[2] = Layer{LayerKind::Dense, Activation::Tanh, Activation::Sigmoid, false, 5, 3, 0};
    } else {  // GRU(5) -> Dense 5 relu -> Dense 3 tanh
      model.layer_count = 3;
      model.layer[0] = Layer{LayerKind::Gru, Activation::Tanh, Activation::Sigmoid, true, p, 5, 0};
      model.layer[1] = Layer{LayerKind::Dense, Activation::Relu, Activation::Sigmoid, false, 5, 5, 0};
      model.layer[2] = Layer{LayerKind::Dense, Activation::Tanh, Activation::Sigmoid, false, 5, 3, 0};
    }
    model.param_count = model.norm_count();
    for (int i = 0; i < model.layer_count; ++i) model.param_count += layer_weight_count(model.layer[i]);
    params.resize(model.param_count);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> d(-0.5f, 0.5f);
    for (float& v : params) v = d(rng);
    for (int i = 0; i < p; ++i) params[size_t(p + i)] = 1.0f;  // in_scale
    for (int i = 0; i < model.n; ++i) params[size_t(2 * p + model.n + i)] = 5.0f;  // out_scale, mm
    model.params = params.data();
    if (finalize_model(model) != Status::Ok) std::abort();
    std::ifstream in(std::string(NLSOFT_SOURCE_MODELS_DIR) + "/" + platform_name(id) + ".nlsm", std::ios::binary);
    const std::vector<uint8_t> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    shipped_params.assign(Cap::weights + 2 * Dims<Cap>::p + 2 * Cap::n, 0.0f);
    Model<Cap> shipped;
    if (!file.empty() && parse_model(file.data(), file.size(), shipped, shipped_params.data(),
                                     uint32_t(shipped_params.size())) == Status::Ok)
      model = shipped;
    Params<Cap> P;
    preset_params(pr, P);
    P.mode = mode;
    if (ctl.configure(&model, P) != Status::Ok) std::abort();
    std::vector<float> u0(pr.m, 0.5f * (pr.u_min + pr.u_max)), y0(pr.n, 0.0f);
    sensors.assign(size_t(pr.w) + 1, 0.1f);
    ctl.reset(u0.data(), y0.data(), sensors.data());
    ref.assign(size_t(Cap::N) * pr.n, 1.0f);
  }
};

template <class Cap>
void control_step(benchmark::State& state, PlatformId id, DerivMode mode) {
  static Rig<Cap>* rig = nullptr;  // the controller is large; build it once per shape
  delete rig;
  rig = new Rig<Cap>(id, mode);
  long k = 0, iterations = 0, allocs = 0;
  for (auto _ : state) {
    // a slowly moving reference keeps the solver working every step
    for (size_t i = 0; i < rig->ref.size(); ++i) rig->ref[i] = 2.0f * std::sin(0.01f * float(k + long(i)));
    const long before = g_allocations.load(std::memory_order_relaxed);
    const StepResult<Cap> r = rig->ctl.step(rig->ref.data(), rig->sensors.data(), nullptr);
    allocs += g_allocations.load(std::memory_order_relaxed) - before;
    benchmark::DoNotOptimize(r.u[0]);
    iterations += r.iterations;
    ++k;
  }
  state.counters["nr_iter"] = double(iterations) / double(k);
  state.counters["allocs_per_step"] = double(allocs) / double(k);
}

void BM_HaselExact(benchmark::State& s) { control_step<HaselCapacity>(s, PlatformId::Hasel, DerivMode::Exact); }
void BM_HaselFd(benchmark::State& s) { control_step<HaselCapacity>(s, PlatformId::Hasel, DerivMode::Fd); }
void BM_TendonExact(benchmark::State& s) { control_step<TendonCapacity>(s, PlatformId::Tendon, DerivMode::Exact); }
void BM_TendonFd(benchmark::State& s) { control_step<TendonCapacity>(s, PlatformId::Tendon, DerivMode::Fd); }

BENCHMARK(BM_HaselExact);
BENCHMARK(BM_HaselFd);
BENCHMARK(BM_TendonExact);
BENCHMARK(BM_TendonFd);

}  // namespace

BENCHMARK_MAIN();
