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
#include <vector>

#include "shared/controller.hpp"
#include <fstream>
#include <iterator>
#include <string>
#include "shared/model_file.hpp"
#include "support/rig_capacities.hpp"
#include "support/shipped_rigs.hpp"

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

// The rig's shipped model (app/models, its rig file's [model] file): the
// cost of a step depends on the shapes and on the iteration count, which
// the benchmark reports.
template <class Cap>
struct Rig {
  Model<Cap> model;
  std::vector<float> params;
  Controller<Cap> ctl;
  std::vector<float> sensors, ref;

  Rig(const char* name, DerivMode mode) {
    const host::Rig& rig = test::shipped_rig_file(name);
    std::ifstream in(std::string(NLSOFT_SOURCE_MODELS_DIR) + "/" + rig.model.file, std::ios::binary);
    const std::vector<uint8_t> file((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    params.assign(Cap::weights + 2 * Dims<Cap>::p + 2 * Cap::n, 0.0f);
    if (file.empty() || parse_model(file.data(), file.size(), model, params.data(), uint32_t(params.size())) != Status::Ok)
      std::abort();
    Params<Cap> P = test::shipped_params<Cap>(name);
    P.mode = mode;
    if (ctl.configure(&model, P) != Status::Ok) std::abort();
    std::vector<float> u0(size_t(rig.m())), y0(size_t(rig.n()), 0.0f);
    for (int i = 0; i < rig.m(); ++i) u0[size_t(i)] = float(rig.inputs[size_t(i)].neutral);
    sensors.assign(size_t(rig.w()) + 1, 0.1f);
    ctl.reset(u0.data(), y0.data(), sensors.data());
    ref.assign(size_t(Cap::N) * size_t(rig.n()), 1.0f);
  }
};

template <class Cap>
void control_step(benchmark::State& state, const char* name, DerivMode mode) {
  static Rig<Cap>* rig = nullptr;  // the controller is large; build it once per shape
  delete rig;
  rig = new Rig<Cap>(name, mode);
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

void BM_HaselExact(benchmark::State& s) { control_step<HaselCapacity>(s, "hasel", DerivMode::Exact); }
void BM_HaselFd(benchmark::State& s) { control_step<HaselCapacity>(s, "hasel", DerivMode::Fd); }
void BM_TendonExact(benchmark::State& s) { control_step<TendonCapacity>(s, "tendon", DerivMode::Exact); }
void BM_TendonFd(benchmark::State& s) { control_step<TendonCapacity>(s, "tendon", DerivMode::Fd); }

BENCHMARK(BM_HaselExact);
BENCHMARK(BM_HaselFd);
BENCHMARK(BM_TendonExact);
BENCHMARK(BM_TendonFd);

}  // namespace

BENCHMARK_MAIN();
