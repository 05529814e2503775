// SQLite recording throughput: samples/s from add_sample() to committed,
// hasel-sized (n 3, m 6, every telemetry field). Target: >= 500 k/s bulk.
//   cmake --build build --target nlsoft-bench-recorder
//   build/tests/bench/nlsoft-bench-recorder
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "app/record/recorder.hpp"

namespace {

using nlsoft::console::Recorder;
using nlsoft::console::RunInfo;
using nlsoft::console::Sample;

Sample hasel_sample(uint64_t k) {
  Sample s;
  s.k = k;
  s.step = uint32_t(k);
  s.time_us = uint32_t(k * 7692);
  s.mask = nlsoft::protocol::telemetry_field::kAll;
  s.n = 3;
  s.m = 6;
  for (int i = 0; i < 3 * 3 + 6; ++i) s.v[i] = float(k) * 0.001f + float(i);
  s.cost = 1234.5f;
  s.iterations = 2;
  s.compute_us = 3.5f;
  return s;
}

void remove_db(const std::string& path) {
  for (const char* suffix : {"", "-wal", "-shm"}) std::remove((path + suffix).c_str());
}

// Bulk: the writer commits as fast as it can (as after a burst or in the
// 10 kHz simulator); one iteration = N samples queued and committed.
void BM_RecorderBulk(benchmark::State& state) {
  const std::string path = std::string(std::getenv("NLSOFT_BENCH_DIR") ? std::getenv("NLSOFT_BENCH_DIR") : "/tmp") + "/nlsoft-bench-recorder-" + std::to_string(::getpid()) + ".db";
  remove_db(path);
  const auto n = uint64_t(state.range(0));
  {
    Recorder::Options o;
    o.queue_capacity = n + 16;
    Recorder rec(path, o);
    RunInfo info;
    info.platform = "hasel";
    info.n = 3;
    info.m = 6;
    const int64_t run = rec.begin_run(info);
    uint64_t k = 0;
    const Sample proto = hasel_sample(0);
    for (auto _ : state) {
      for (uint64_t i = 0; i < n; ++i) {
        Sample s = proto;
        s.k = k;
        s.step = uint32_t(k++);
        if (!rec.add_sample(run, s)) state.SkipWithError("queue full");
      }
      rec.flush();
    }
    state.SetItemsProcessed(int64_t(k));
    state.counters["dropped"] = double(rec.dropped_samples());
  }
  remove_db(path);
}
BENCHMARK(BM_RecorderBulk)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime();

// The producer's side alone: what the link thread pays per sample.
void BM_RecorderAddSample(benchmark::State& state) {
  const std::string path = "/tmp/nlsoft-bench-recorder-add-" + std::to_string(::getpid()) + ".db";
  remove_db(path);
  {
    Recorder rec(path);
    RunInfo info;
    info.n = 3;
    info.m = 6;
    const int64_t run = rec.begin_run(info);
    Sample s = hasel_sample(0);
    uint64_t k = 0;
    for (auto _ : state) {
      s.k = k++;
      benchmark::DoNotOptimize(rec.add_sample(run, s));
      if ((k & 0xFFFF) == 0) {
        state.PauseTiming();
        rec.flush();
        state.ResumeTiming();
      }
    }
    state.SetItemsProcessed(int64_t(k));
  }
  remove_db(path);
}
BENCHMARK(BM_RecorderAddSample);

}  // namespace

BENCHMARK_MAIN();
