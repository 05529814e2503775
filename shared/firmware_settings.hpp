#pragma once
// The firmware's own settings, listed after the controller's parameter
// table (shared/params.hpp) with ids from 100. Their defaults live here, and
// the controller's in the rig file (rigs/*.toml [controller]), so the console
// knows every value a freshly booted firmware holds (`params diff`, `params reset`).
#include <cstdint>

namespace nlsoft {

enum class FwParamId : uint16_t {
  WatchdogMs = 100,  // link silence during a run before the safe state, 0 = off
  SafeState = 101,   // 0 hold the last command, 1 actuators to neutral
};

struct FwSettings {
  uint16_t watchdog_ms = 1000;
  uint8_t safe_state = 1;
};

}  // namespace nlsoft
