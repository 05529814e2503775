#pragma once
// A closed-loop run of hasel as a console records one from a board (not
// the simulator): one sample of step and u. What replays and tunes on
// replays must refuse, naming the board's firmware.
#include <cstdint>
#include <string>

#include "app/record/recorder.hpp"
#include "app/record/sample.hpp"
#include "protocol/messages.hpp"

namespace nlsoft::test {

inline int64_t record_a_boards_run(const std::string& db) {
  console::Recorder rec(db);
  console::RunInfo ri;
  ri.platform = "hasel";
  ri.firmware = "nlsoft-f446 0.1.0";
  ri.n = 3;
  ri.m = 6;
  ri.loop_rate_hz = 130;
  ri.reference = R"({"kind":"swirl","hold":10,"a":4,"b":4,"c":4,"center":[0,0,4],"omega":0,"lambda":0,"scale":1,"levels":[]})";
  const int64_t id = rec.begin_run(ri);
  console::Sample s;
  s.n = 3;
  s.m = 6;
  s.mask = protocol::telemetry_field::kStep | protocol::telemetry_field::kU;
  rec.add_sample(id, s);
  rec.end_run(id, "completed", 1, 0);
  return id;
}

}  // namespace nlsoft::test
