#pragma once
// Offline closed loop on the host: simulated plant + controller (MPC or the
// PID baseline) + reference, step by step as the firmware runs them, with a
// trace of everything the metrics need.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "shared/model.hpp"
#include "shared/plant_generic.hpp"
#include "shared/params.hpp"
#include "shared/pid.hpp"
#include "shared/plant_registry.hpp"
#include "shared/reference.hpp"

namespace nlsoft::console {

enum class ControllerKind { Mpc, Pid };

// A plant that stands in for the simulated one (a plant model, when a
// board's run is replayed): its dimensions and period, where it rests
// (the neutral inputs it wants in u), a step under u, and its output and
// sensors now. No noise, no settling.
struct StandInPlant {
  int m = 0, n = 0, w = 0;
  float dt = 0.0f;
  std::function<void(float* u)> rest;
  std::function<void(const float* u)> step;
  std::function<void(float* y, float* l)> read;
};

struct LoopSetup {
  // Set by the caller: left unset, no hand-written plant is chosen for it
  // (Generic without a spec is refused).
  PlantKind plant = PlantKind::Generic;
  // A rig's generic plant instead of the hand-written `plant` (the caller
  // keeps it alive); `plant_name` names either in errors ("" : the plant's).
  const GenericPlantSpec* generic = nullptr;
  std::string plant_name;
  ControllerKind controller = ControllerKind::Mpc;
  const Model<HostCapacity>* model = nullptr;  // required for Mpc
  // Pid: the rig's [pid] (use_rig_pid), one loop per axis.
  PidGains pid{};
  float pid_output_scale = 1.0f, pid_d_filter_tau = 0.0f;
  Params<HostCapacity> params{};
  RefParams reference{};
  // The reference paths drive three outputs (shared/reference.hpp); an
  // output beyond the third is held at ref_hold[j].
  float ref_hold[HostCapacity::n] = {};
  long steps = 0;          // control steps to run
  long settle_steps = 0;   // neutral input before the run, so the plant starts at rest
  uint32_t seed = 1;       // plant noise
  const StandInPlant* stand_in = nullptr;  // in the simulated plant's place
};

// Row k holds the state after input u(k) was applied: y_ref(k+1), the
// prediction y_hat(k+1) made at k, and the plant's y_true(k+1).
struct Trace {
  int m = 0, n = 0;
  float dt = 0.0f;
  std::vector<float> y_ref, y_hat, y_true, u;  // rows of n (u: m)
  std::vector<float> cost;
  std::vector<uint8_t> iterations, flags;
  std::vector<float> solve_us;  // wall time of each controller step (host)
  long rows() const { return long(cost.size()); }
};

using Progress = std::function<void(long done, long total)>;

// Throws CliError when the setup cannot run (no model for MPC, dimension
// mismatch between model and platform, PID gains or limits Pid refuses, a
// PID on a plant whose inputs and outputs do not pair up).
Trace run_closed_loop(const LoopSetup& setup, const Progress& progress = {});

}  // namespace nlsoft::console
