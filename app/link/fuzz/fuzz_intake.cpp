// libFuzzer target for the console's whole intake: bytes as they come from
// the port, through the session (decoder, the checks against INFO, the
// escaping of text), into the samples, the recorder and the live buffer the
// TUI's plots read. Built with clang under ASan+UBSan (NLSOFT_FUZZ=ON, see
// app/link/fuzz/CMakeLists.txt); CI runs it briefly in `cmake/dev sanitize`:
//   build-fuzz/app/link/fuzz/nlsoft-fuzz-intake -max_total_time=60 CORPUS protocol/fuzz/corpus
//
// Input: byte 0 picks the firmware's INFO (m, n, w, or none yet), byte 1
// whether a run records, whether it asked for the sensors (SENSOR_STREAM)
// and the chunk size the port delivers; the rest is
// the line. Every sample that arrives must be of INFO's shape and finite,
// every LOG line free of what a terminal acts on.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "app/link/session.hpp"
#include "app/live/active_run.hpp"
#include "app/live/sample_intake.hpp"
#include "app/record/recorder.hpp"

namespace c = nlsoft::console;
namespace p = nlsoft::protocol;

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

// INFOs a firmware may send: the shipped rigs' shapes and the largest.
p::Info info_for(uint8_t pick) {
  static const uint8_t shapes[][3] = {{1, 1, 0}, {6, 3, 18}, {2, 3, 11}, {8, 6, 32}, {15, 15, 28}, {1, 1, 58 - 2}};
  const auto& s = shapes[pick % (sizeof shapes / sizeof shapes[0])];
  p::Info info;
  info.m = s[0];
  info.n = s[1];
  info.w = s[2];
  info.loop_rate_hz = 100;
  return info;
}

bool text_safe(const char* text) {
  for (const unsigned char* b = reinterpret_cast<const unsigned char*>(text); *b; ++b)
    if (*b < 0x20 || *b == 0x7f || *b == 0x9b) return false;
  return true;
}

// One recorder for the process (a database per input would cost more than
// the input), recreated now and then so that its file stays small.
struct Rig {
  std::string dir;
  std::unique_ptr<c::Recorder> recorder;
  std::unique_ptr<c::ActiveRun> run;
  std::unique_ptr<c::SampleIntake> intake;
  int64_t run_id = 0;
  int uses = 0;

  void renew() {
    intake.reset();
    run.reset();
    recorder.reset();
    if (!dir.empty()) std::remove((dir + "/fuzz.db").c_str());
    if (dir.empty()) {
      char tmpl[] = "/tmp/nlsoft-fuzz-intake-XXXXXX";
      check(::mkdtemp(tmpl) != nullptr);
      dir = tmpl;
    }
    std::remove((dir + "/fuzz.db-wal").c_str());
    std::remove((dir + "/fuzz.db-shm").c_str());
    recorder = std::make_unique<c::Recorder>(dir + "/fuzz.db");
    run = std::make_unique<c::ActiveRun>(*recorder);
    intake = std::make_unique<c::SampleIntake>(*run, nullptr);
    c::RunInfo ri;
    ri.label = "fuzz";
    ri.n = 15;
    ri.m = 15;
    ri.loop_rate_hz = 100;
    run_id = recorder->begin_run(ri);
    uses = 0;
  }
};

Rig& rig() {
  static Rig r;
  if (!r.recorder || ++r.uses > 20000) r.renew();
  return r;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const uint8_t pick = data[0], mode = data[1];
  data += 2;
  size -= 2;
  Rig& r = rig();
  c::ActiveRun& run = *r.run;
  const bool recording = (mode & 0x80) != 0;
  run.k = 0;
  run.lost = 0;
  run.have_last_step = false;
  run.step_went_back = false;
  run.left_state = 0;
  run.left_watchdog = 0;
  run.id = recording ? r.run_id : 0;

  c::Session session;
  const bool known = pick < 0xf0;  // else: no INFO yet, only the capacity is checked
  const p::Info info = info_for(pick);
  if (known) session.take_identity(info);
  run.sensors_w = (mode & 0x40) != 0 ? info.w : 0;
  c::SampleIntake& intake = *r.intake;
  session.on_telemetry([&](const p::Telemetry& t, uint32_t lost) {
    check(!known || (t.n == info.n && t.m == info.m));
    check(t.n <= p::kMaxTelemetryDim && t.m <= p::kMaxTelemetryDim);
    for (int i = 0; i < t.n; ++i)
      check(!(t.mask & p::telemetry_field::kYTrue) || std::isfinite(t.y_true[i]));
    intake.on_telemetry(t, lost);
  });
  session.on_ident_sample([&](const p::IdentSample& s, uint32_t lost) {
    check(!known || (s.m == info.m && (s.n == 0 || s.n == info.n) && s.w == info.w));
    check(s.m <= p::kMaxTelemetryDim && s.n <= p::kMaxTelemetryDim);
    intake.on_ident_sample(s, lost);
  });
  session.on_sensor_health([&](const p::SensorHealth& h) { intake.on_sensor_health(h); });
  session.on_sensor_sample([&](const p::SensorSample& s) {
    check(!known || s.w == info.w);
    check(s.w <= p::kMaxSensorChannels);
    for (int i = 0; i < s.w; ++i) check(std::isfinite(s.l[i]));
    intake.on_sensor_sample(s);
  });
  session.on_status([&](const p::Status& s) { intake.on_status(s); });
  session.on_log([&](const p::Log& l) { check(text_safe(l.text)); });

  const size_t chunk = 1 + (mode & 0x3f);
  for (size_t pos = 0; pos < size; pos += chunk) session.on_bytes(data + pos, std::min(chunk, size - pos));

  // What the TUI's plots read, sample by sample.
  for (const c::Sample& s : intake.live().snapshot(64)) {
    check(s.n <= p::kMaxTelemetryDim && s.m <= p::kMaxTelemetryDim && s.w <= c::Sample::kMaxSensors);
    check(s.u() + s.m <= s.v + c::Sample::kMaxFloats);
  }
  intake.live().clear();
  run.id = 0;
  return 0;
}
