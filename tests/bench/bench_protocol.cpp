// Protocol throughput: frames/s through the decoder (the firmware's receive
// path and the console's telemetry path), the encoder, and the CRC alone.
//   cmake --build build --target nlsoft-bench-protocol
//   build/tests/bench/nlsoft-bench-protocol

#include <benchmark/benchmark.h>

#include <vector>

#include "protocol/crc.hpp"
#include "protocol/decoder.hpp"
#include "protocol/encoder.hpp"
#include "protocol/messages.hpp"

namespace np = nlsoft::protocol;

namespace {

np::Telemetry hasel_telemetry(uint16_t tseq) {
  np::Telemetry t;
  t.tseq = tseq;
  t.mask = np::telemetry_field::kAll;
  t.n = 3;
  t.m = 6;
  t.step = 1000u + tseq;
  t.time_us = 7692u * tseq;
  for (int i = 0; i < 3; ++i) {
    t.y_ref[i] = 0.1f * static_cast<float>(i + tseq % 7);
    t.y_hat[i] = t.y_ref[i] + 0.01f;
    t.y_true[i] = t.y_ref[i] - 0.01f;
  }
  for (int i = 0; i < 6; ++i) t.u[i] = 0.2f * static_cast<float>(i);
  t.cost = 12.5f;
  t.iterations = 3;
  t.compute_ticks = 2100;
  return t;
}

std::vector<uint8_t> telemetry_stream(size_t frames) {
  std::vector<uint8_t> s;
  uint8_t buf[np::kWireBufferSize];
  for (size_t i = 0; i < frames; ++i) {
    const size_t n = np::encode(hasel_telemetry(static_cast<uint16_t>(i)),
                                static_cast<uint8_t>(i), 0, buf, sizeof buf);
    s.insert(s.end(), buf, buf + n);
  }
  return s;
}

constexpr size_t kFrames = 1024;

// Decoder fed in USB-sized chunks: the console's receive loop.
void BM_DecodeTelemetryChunked(benchmark::State& state) {
  const auto stream = telemetry_stream(kFrames);
  const size_t chunk = static_cast<size_t>(state.range(0));
  np::Decoder d;
  for (auto _ : state) {
    size_t pos = 0;
    while (pos < stream.size()) {
      const size_t avail = std::min(chunk, stream.size() - pos);
      size_t off = 0;
      while (off < avail) {
        np::DecodeResult r;
        off += d.feed(stream.data() + pos + off, avail - off, r);
        benchmark::DoNotOptimize(r.kind);
      }
      pos += avail;
    }
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kFrames));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * stream.size()));
}
BENCHMARK(BM_DecodeTelemetryChunked)->Arg(64)->Arg(4096);

// One byte per call: the firmware's UART interrupt path.
void BM_DecodeTelemetryBytewise(benchmark::State& state) {
  const auto stream = telemetry_stream(kFrames);
  np::Decoder d;
  for (auto _ : state) {
    for (uint8_t b : stream) {
      const np::DecodeResult r = d.push(b);
      benchmark::DoNotOptimize(r.kind);
    }
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kFrames));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * stream.size()));
}
BENCHMARK(BM_DecodeTelemetryBytewise);

// Decode plus typed unpack: what the console does per telemetry frame.
void BM_DecodeAndUnpackTelemetry(benchmark::State& state) {
  const auto stream = telemetry_stream(kFrames);
  np::Decoder d;
  np::Telemetry t;
  for (auto _ : state) {
    size_t pos = 0;
    while (pos < stream.size()) {
      np::DecodeResult r;
      pos += d.feed(stream.data() + pos, stream.size() - pos, r);
      if (r.kind == np::DecodeResult::Kind::Frame) {
        benchmark::DoNotOptimize(np::unpack(r.frame, t));
      }
    }
    benchmark::DoNotOptimize(t.cost);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * kFrames));
}
BENCHMARK(BM_DecodeAndUnpackTelemetry);

// A short request (PARAM_GET), the firmware's typical inbound frame.
void BM_DecodeSmallRequest(benchmark::State& state) {
  np::ParamGet g;
  g.id = 3;
  uint8_t buf[np::kWireBufferSize];
  const size_t n = np::encode(g, 1, 0, buf, sizeof buf);
  np::Decoder d;
  for (auto _ : state) {
    np::DecodeResult r;
    d.feed(buf, n, r);
    benchmark::DoNotOptimize(r.kind);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}
BENCHMARK(BM_DecodeSmallRequest);

// Pack + CRC + COBS of a full hasel telemetry frame: the firmware's send path.
void BM_EncodeTelemetry(benchmark::State& state) {
  const np::Telemetry t = hasel_telemetry(1);
  uint8_t buf[np::kWireBufferSize];
  uint8_t seq = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(np::encode(t, seq++, 0, buf, sizeof buf));
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}
BENCHMARK(BM_EncodeTelemetry);

void BM_Crc16(benchmark::State& state) {
  std::vector<uint8_t> data(static_cast<size_t>(state.range(0)), 0xA5);
  for (auto _ : state) benchmark::DoNotOptimize(np::crc16(data.data(), data.size()));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * data.size()));
}
BENCHMARK(BM_Crc16)->Arg(253);

void BM_Crc32(benchmark::State& state) {
  std::vector<uint8_t> data(static_cast<size_t>(state.range(0)), 0xA5);
  for (auto _ : state) benchmark::DoNotOptimize(np::crc32(data.data(), data.size()));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * data.size()));
}
BENCHMARK(BM_Crc32)->Arg(4096);

}  // namespace

BENCHMARK_MAIN();
