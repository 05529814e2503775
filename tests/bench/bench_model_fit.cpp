// `model fit` on 50,000 samples of hasel (m 6, n 3, w 0; its shipped
// network shape, Dense 5 relu, 5 relu, 3 linear): the rows built, the network
// run as the firmware runs it (one-step and free run), the ARX baseline
// fitted by least squares and run the same way, scored. Target: < 1 s.
//   cmake -B build -DNLSOFT_BENCHMARKS=ON && cmake --build build --target nlsoft-bench-model-fit
//   build/tests/bench/nlsoft-bench-model-fit
#include <benchmark/benchmark.h>

#include "app/model/excitation.hpp"
#include "app/model/model_fit.hpp"
#include "app/model/train.hpp"
#include "support/shipped_rigs.hpp"

namespace {

using namespace nlsoft::model;

void BM_ModelFit50k(benchmark::State& state) {
  const PlantTarget target = nlsoft::test::shipped_target("hasel");
  // A model trained briefly on other data: its accuracy is not what is timed.
  TrainOptions o = default_options(target);
  o.epochs = 1;
  const TrainResult trained = train(generate_excitation(target, 4000, 1), target, o);
  const Series s = generate_excitation(target, 50000, 2);
  for (auto _ : state) {
    const Dataset d = build_dataset(s, o.nd, o.dd);
    const ArxModel arx = fit_arx(d, d.pieces);
    const FitSection f = fit_section("bench", trained.model, &arx, d, d.pieces, target);
    benchmark::DoNotOptimize(f.outputs.data());
  }
  state.SetItemsProcessed(state.iterations() * s.rows());
}
BENCHMARK(BM_ModelFit50k)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
