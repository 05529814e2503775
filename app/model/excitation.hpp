#pragma once
// Identification data from a simulated plant (paper, "Data Collection"):
// a sequence of excitation segments, each one of
//   steps  - every actuator jumps to a new level after a random hold,
//   walk   - a smoothed random walk,
//   chirp  - a sine whose frequency sweeps over the plant's bandwidth,
//   paper  - msd only: the paper's u(t) = 1000 sin t cos t N/kg,
// with a small dither on top so every sample also carries the local
// input->output sensitivity the controller differentiates.
// Levels are drawn around a random common level for the HASEL platform, so
// the mean extension (platform height) sweeps the whole task space instead
// of clustering at the middle as independent draws would.
#include <cstdint>

#include "app/model/plant_target.hpp"
#include "app/model/series.hpp"
#include "shared/plant_registry.hpp"

namespace nlsoft::model {

// 120000 steps: 2 min of msd at 1 kHz, 15 of hasel at 130 Hz.
long default_steps(const PlantTarget& t);

// Row k holds u(k), y(k), l(k) of the hand-written plant `kind`; the plant
// then advances one period with u(k) held. Deterministic for (kind, steps,
// seed); throws PipelineError for the generic plant (it needs its spec).
Series generate_excitation(PlantKind kind, long steps, uint32_t seed);
// The same for a rig's plant: a named one exactly as above, a generic one
// with time scales from its lags; throws PipelineError for a rig without one.
Series generate_excitation(const PlantTarget& t, long steps, uint32_t seed);

// y of the plant resting at its neutral input: the point the outputs are
// normalised around.
void neutral_output(PlantKind kind, double* y);
// A rig without a plant: its y_rest; a generic plant whose spec it refuses
// throws PipelineError.
void neutral_output(const PlantTarget& t, double* y);

}  // namespace nlsoft::model
