#pragma once
// A rig put into an offline loop (closed_loop.hpp): its simulated plant, the
// outputs the reference paths do not drive held mid-range, and the PID
// baseline its file gives ([pid], docs/rig-file.md). `simulate` and `runs
// replay --controller pid` set their loops up here, so both run the same one.
#include <fmt/format.h>

#include "app/simulate/closed_loop.hpp"
#include "host/files/cli_error.hpp"
#include "host/rig/rig.hpp"
#include "host/rig/rig_plant.hpp"

namespace nlsoft::console {

// The rig's plant: its generic spec, kept in `generic` (which must outlive
// the loop), or its hand-written kind. Throws CliError for a rig without a
// simulated plant, naming `what` (the command).
inline void use_rig_plant(const host::Rig& rig, const char* what, GenericPlantSpec& generic, LoopSetup& setup) {
  if (host::has_generic_plant(rig)) {
    generic = host::generic_plant_spec(rig);
    setup.generic = &generic;
  } else {
    setup.plant = host::simulated_plant(rig, what).kind;
  }
  setup.plant_name = rig.name;
  // Outputs beyond the paths' three hold the middle of their range.
  for (int j = kRefMaxDim; j < rig.n(); ++j)
    setup.ref_hold[j] = float(0.5 * (rig.outputs[size_t(j)].min + rig.outputs[size_t(j)].max));
}

// Throws CliError for a rig whose file has no [pid] table.
inline void use_rig_pid(const host::Rig& rig, LoopSetup& setup) {
  if (!rig.pid.given)
    throw host::CliError(fmt::format(
        "rig '{}' ({}) has no [pid] table: the PID baseline needs its gains (kp, ki, kd; docs/rig-file.md, "
        "\"[pid]\")",
        rig.name, rig.file));
  setup.controller = ControllerKind::Pid;
  setup.pid = {float(rig.pid.kp), float(rig.pid.ki), float(rig.pid.kd)};
  setup.pid_output_scale = float(rig.pid.output_scale);
  setup.pid_d_filter_tau = float(rig.pid.d_filter_tau);
}

}  // namespace nlsoft::console
