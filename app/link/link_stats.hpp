#pragma once
// What the status bar shows about the link, as one copyable snapshot.
#include <cstdint>

namespace nlsoft::console {

struct LinkStats {
  bool connected = false;
  bool silent = false;  // port open but no valid frame for the silence limit
  double frames_per_s = 0, bytes_per_s = 0;
  uint64_t frames = 0, bytes = 0;
  uint64_t crc_errors = 0, decode_errors = 0;  // ours, as receiver
  uint64_t telemetry_frames = 0, lost_telemetry = 0;
  // Sample frames dropped as they arrived: dimensions other than INFO's, or
  // values not finite (app/link/sample_check.hpp). Counted lost as well.
  uint64_t refused_frames = 0;
  uint64_t timeouts = 0, retransmits = 0, stale_replies = 0, reconnects = 0;
  // Valid frames that were requests, as the console sends them: a firmware
  // never sends one, so they are our own frames coming back (an echoing line).
  uint64_t echoed_frames = 0;
  // From the firmware's STATUS heartbeat.
  bool have_status = false;
  double loop_rate_hz = 0;        // measured from step counts while running, else nominal
  double compute_mean_us = 0, compute_max_us = 0;
  uint32_t fw_crc_errors = 0, fw_frame_errors = 0, fw_tx_dropped = 0, fw_loop_overruns = 0;
  uint8_t run_state = 0;
  uint32_t run_id = 0, step = 0;
};

}  // namespace nlsoft::console
