// The nlsoft firmware on the MPS2 AN386 (Cortex-M4F): the portable core over
// UART0 and SysTick, with either the simulated plant in the loop
// (NLSOFT_HIL=1, the image QEMU runs) or stub actuators (the real-board
// image). Serves the link, runs one control step per SysTick period, and
// sleeps (WFI) when neither has work: under QEMU an idle guest then costs no
// host CPU and virtual time keeps pace with real time.
#include "firmware/core/firmware.hpp"
#include "firmware/ports/mps2-an386/cmsdk_uart.hpp"
#include "firmware/ports/mps2-an386/platform_config.hpp"
#include "firmware/ports/mps2-an386/systick.hpp"
#include "shared/platform.hpp"

#if NLSOFT_HIL
#include "firmware/ports/mps2-an386/hil_hal.hpp"
#else
#include "firmware/ports/mps2-an386/board_hal.hpp"
#endif

#if NLSOFT_HAVE_MODEL
extern "C" const uint8_t nlsoft_model_begin[], nlsoft_model_end[];
#endif

namespace {

using namespace nlsoft;
using namespace nlsoft::fw::an386;
using Fw = fw::Firmware<Cap, kTxCapacity>;

constexpr uint32_t kBaud = 115200;
// Preset rates are whole numbers of hertz (130, 120, 1000).
constexpr uint32_t kRateHz = uint32_t(kPresets[uint8_t(kPlatform)].rate_hz);
constexpr uint32_t kPeriodTicks = kCoreClockHz / kRateHz;

#if NLSOFT_HIL
using PortHal = HilHal<Plant>;
PortHal g_hal(1.0f / float(kRateHz));
constexpr const char* kName = "nlsoft-an386-hil";
#else
using PortHal = BoardHal;
PortHal g_hal;
constexpr const char* kName = "nlsoft-an386";
#endif

alignas(4) uint8_t g_model_staging[kModelFileMax];
uint8_t g_table_staging[kTableFileMax];
float g_table_points[kTableFloats];

Fw g_fw(g_hal, fw::Identity{kPlatform, kName, 0, 1, 0, kRateHz, NLSOFT_HIL != 0},
        fw::Buffers{g_model_staging, sizeof g_model_staging, g_table_staging,
                    sizeof g_table_staging, g_table_points, kTableFloats});

}  // namespace

int main() {
  systick_start(kPeriodTicks);
  uart_start(kBaud);
#if NLSOFT_HAVE_MODEL
  // A refused model leaves the firmware serving the link; INFO shows
  // model_hash 0 and a run is refused until a model is uploaded.
  (void)g_fw.begin(nlsoft_model_begin, size_t(nlsoft_model_end - nlsoft_model_begin));
#else
  (void)g_fw.begin(nullptr, 0);
#endif

  uint32_t done = systick_periods();
  for (;;) {
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
    if (systick_periods() == done && !uart_busy()) __asm volatile("wfi");
    __asm volatile("cpsie i" ::: "memory");
  }
}
