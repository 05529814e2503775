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

#include "app/model/series.hpp"
#include "shared/platform_id.hpp"

namespace nlsoft::pipeline {

long default_steps(PlatformId id);

// Row k holds u(k), y(k), l(k); the plant then advances one period with
// u(k) held. Deterministic for (id, steps, seed).
Series generate_excitation(PlatformId id, long steps, uint32_t seed);

// y of the plant resting at its neutral input: the point the outputs are
// normalised around.
void neutral_output(PlatformId id, double* y);

}  // namespace nlsoft::pipeline
