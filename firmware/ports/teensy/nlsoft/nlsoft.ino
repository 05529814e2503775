// nlsoft on a Teensy 3.6 / 4.x: the learned-model predictive controller,
// tuned live from nlsoft-console over the USB serial port.
//
//   1. Generate the rig's header beside this sketch (its values and the
//      capacity sized for it; README.md):
//        nlsoft-console firmware header --rig msd --out firmware/ports/teensy/nlsoft
//   2. Generate model_data.h from the trained model (README.md):
//        xxd -i -n nlsoft_model app/models/msd.nlsm > model_data.h
//   3. Fill in board_actuate() and board_read_sensors() for your rig.
//   4. Build with Teensyduino (README.md has the include path), upload, then
//        nlsoft-console /dev/ttyACM0
//
// The loop: serve the link continuously, run one control step per period
// (read sensors -> Newton-Raphson -> clamp -> actuate -> telemetry), count
// late steps as overruns. No heap: every buffer below is static.
#include "firmware/core/firmware.hpp"
#include "model_data.h"  // unsigned char nlsoft_model[]; unsigned int nlsoft_model_len;
#include "shared/model_file.hpp"
#include "nlsoft_rig.hpp"  // kRig, Cap: `nlsoft-console firmware header --rig RIG`
#include "shared/version.hpp"
#include "teensy_hal.hpp"

namespace {

using Cap = nlsoft::fw::cortex_m::Cap;
using Fw = nlsoft::fw::Firmware<Cap, 1024>;

// The rig: dimensions, limits, defaults, start-up reference (shared/rig_config.hpp).
constexpr const nlsoft::RigConfig& kRig = nlsoft::fw::cortex_m::kRig;
constexpr uint32_t kRateHz = uint32_t(kRig.rate_hz);

// An upload in transit (then the uploaded model in force), and an uploaded
// reference table.
alignas(4) uint8_t g_model_staging[nlsoft::model_file_max<Cap>()];
constexpr uint32_t kTableFloats = 512 * Cap::n;
float g_table_points[kTableFloats];
uint8_t g_table_staging[8 + 4 * kTableFloats];

TeensyHal g_hal;
Fw g_fw(g_hal, nlsoft::fw::Identity{&kRig, "nlsoft-teensy", nlsoft::kVersionMajor, nlsoft::kVersionMinor,
                                            nlsoft::kVersionPatch, kRateHz, false},
        nlsoft::fw::Buffers{g_model_staging, sizeof g_model_staging, g_table_staging, sizeof g_table_staging,
                            g_table_points, kTableFloats});
uint32_t g_next_us = 0;

}  // namespace

// ---- the rig: replace these two with your actuators and sensors -----------
// u[i] is inside [u_min, u_max] (the rig's limits, tunable from the console).
void board_actuate(const float* u, int m) {
  static const uint8_t pins[] = {2, 3, 4, 5, 6, 7};  // PWM pins driving the HASEL supplies
  for (int i = 0; i < m && i < int(sizeof pins); ++i) analogWrite(pins[i], int(u[i] * 4095.0f));
}
// l[i]: the w proprioceptive channels, in the units the model was trained on.
void board_read_sensors(float* l, int w) {
  for (int i = 0; i < w; ++i) l[i] = float(analogRead(uint8_t(A0 + i))) * (1.0f / 1023.0f);
}

void setup() {
  Serial.begin(115200);  // USB: the rate is ignored, the link runs at USB speed
  analogWriteResolution(12);
  g_hal.begin();
  // A refused model keeps the link up: INFO reports no model, runs wait for an upload.
  g_fw.begin(nlsoft_model, nlsoft_model_len);
  g_next_us = micros();
}

void loop() {
  g_fw.poll();
  const uint32_t now = micros();
  const uint32_t period_us = 1000000u / kRateHz;
  if (int32_t(now - g_next_us) < 0) return;
  g_fw.step();
  g_next_us += period_us;
  if (int32_t(now - g_next_us) >= 0) {  // a whole period late: count it and re-anchor
    g_fw.count_overrun();
    g_next_us = now + period_us;
  }
}
