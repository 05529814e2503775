// The nlsoft firmware on a Cortex-M4F board: the portable core over the
// board's link and SysTick, with either the simulated plant in the loop
// (NLSOFT_HIL=1) or the port's rig HAL (rig_hal.hpp, found on the port's
// include path). Serves the link, runs one control step per SysTick period,
// and sleeps (WFI) when neither has work: under QEMU an idle guest then
// costs no host CPU and virtual time keeps pace with real time.
#include "firmware/core/firmware.hpp"
#include "firmware/ports/cortex-m/board.hpp"
#include "firmware/ports/cortex-m/platform_config.hpp"
#include "firmware/ports/cortex-m/systick.hpp"
#include "shared/version.hpp"

#if NLSOFT_HIL
#include "firmware/ports/cortex-m/hil_hal.hpp"
#else
#include "rig_hal.hpp"
#endif

#ifndef NLSOFT_FIRMWARE_NAME
#error "the build names the image: NLSOFT_FIRMWARE_NAME"
#endif

#if NLSOFT_HAVE_MODEL
extern "C" const uint8_t nlsoft_model_begin[], nlsoft_model_end[];
#endif

namespace {

using namespace nlsoft;
using namespace nlsoft::fw::cortex_m;
constexpr uint32_t kBaud = 115200;
// Rig rates are whole numbers of hertz (130, 120, 1000).
constexpr uint32_t kRateHz = uint32_t(kRig.rate_hz);

#if NLSOFT_HIL
using PortHal = HilHal<Plant>;
PortHal g_hal(1.0f / float(kRateHz));
constexpr bool kChips = false;  // the plant gives every sensor channel, the chips' too
#else
using PortHal = RigHal<kRig.m, kRig.w>;
PortHal g_hal;
constexpr bool kChips = kRigDeviceCount > 0;
#endif

// A port whose part keeps settings in its flash (stm32f4) builds with
// NLSOFT_BOARD_SETTINGS=1. The image carries the services its rig file
// asks for ([firmware] features) that the board can have, and the chips'
// sampler when it reads chips; nothing else is compiled in.
#ifndef NLSOFT_BOARD_SETTINGS
#define NLSOFT_BOARD_SETTINGS 0
#endif
constexpr uint32_t kBoardFeatures = fw::kDefaultFeatures | (NLSOFT_BOARD_SETTINGS ? feature::kSettings : 0u);
constexpr uint32_t kFeatures = (kRig.features & kBoardFeatures) | (kChips ? feature::kChips : 0u);
constexpr bool kSettings = (kFeatures & feature::kSettings) != 0;

using Fw = fw::Firmware<Cap, kTxCapacity, kFeatures>;

// Staging for what the image receives; a word where it receives nothing.
constexpr size_t kModelStaging = kFeatures & feature::kModelUpload ? kModelFileMax : 4;
constexpr size_t kTableStaging = kFeatures & feature::kTableUpload ? kTableFileMax : 4;
constexpr uint32_t kTablePointFloats = kFeatures & feature::kTableUpload ? kTableFloats : 1;
alignas(4) uint8_t g_model_staging[kModelStaging];
uint8_t g_table_staging[kTableStaging];
float g_table_points[kTablePointFloats];

// has_y_true: the simulated plant's output on a HIL image, the rig's ADC
// outputs on a board whose rig file wires every output.
Fw g_fw(g_hal,
        fw::Identity{&kRig, NLSOFT_FIRMWARE_NAME, kVersionMajor, kVersionMinor, kVersionPatch, kRateHz,
                     PortHal::kMeasuresOutput},
        fw::Buffers{g_model_staging, sizeof g_model_staging, g_table_staging,
                    sizeof g_table_staging, g_table_points, kTablePointFloats});

// A template so that, without chips, the call is never compiled against a
// HAL that has no sampler (a discarded branch outside a template still is).
template <class H>
void attach_chips(Fw& fw, H& hal) {
  if constexpr (kChips) fw.attach_sensors(hal.sensors());
}

// The settings store over the board's two sectors and a record's buffer;
// without a flash that answers the image has no SETTINGS.
template <class F>
void attach_settings(F& fw) {
  if constexpr (kSettings) {
    constexpr size_t kMax = fw::settings_payload_max(fw::ParamService<Cap>::count());
    static uint8_t payload[kMax];
    const fw::board::SettingsFlash flash = fw::board::settings_flash();
    if (!flash.part) return;
    static fw::SettingsStore store(*flash.part, flash.sector_a, flash.sector_b);
    fw.attach_settings(store, payload, sizeof payload);
  }
}

}  // namespace

int main() {
  fw::board::start(kBaud);
  g_hal.start();
  // The rig's sensor chips (a board image of a rig with [[device]] tables),
  // begun with the firmware, sampled between its steps.
  attach_chips(g_fw, g_hal);
  attach_settings(g_fw);
  // The period follows the clock the board reached, not the one it asked
  // for: a part left on its reset oscillator still steps at the preset rate.
  systick_start(fw::board::core_clock_hz() / kRateHz);
#if NLSOFT_HAVE_MODEL
  // A refused model leaves the firmware serving the link; INFO shows
  // model_hash 0 and a run is refused until a model is uploaded.
  (void)g_fw.begin(nlsoft_model_begin, size_t(nlsoft_model_end - nlsoft_model_begin));
#else
  (void)g_fw.begin(nullptr, 0);
#endif

  uint32_t done = systick_periods();
  for (;;) {
    fw::board::watchdog_kick();
    g_fw.poll();
    const uint32_t due = systick_periods();
    if (due != done) {
      // More than one period elapsed since the last step: those were missed.
      for (uint32_t late = due - done; late > 1; --late) g_fw.count_overrun();
      done = due;
      g_fw.step();
      g_hal.advance();
      continue;
    }
    // Sleep until the next period or received byte. Interrupts are masked
    // across the check so one arriving just before WFI still wakes it.
    __asm volatile("cpsid i" ::: "memory");
    if (systick_periods() == done && !fw::board::serial_busy()) __asm volatile("wfi");
    __asm volatile("cpsie i" ::: "memory");
  }
}
