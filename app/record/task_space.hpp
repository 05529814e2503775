#pragma once
// The size of each rig's task space per output axis, in its output units:
// what the `nrmse_space` metric divides by. A reference's own range is no
// measure for a hold or a short step (nrmse is NaN or huge there); the
// space the rig can reach is, and it is the same for every run on the rig,
// so runs with different references compare.
#include <string>
#include <vector>

namespace nlsoft::console {

// The `span` of each [[output]] of the installed rig file of that name
// (rigs/hasel.toml: 23.0 x 20.2 x 19.2 mm, tendon 40.4 x 28.3 x 35.0 mm, the
// paper's; msd 2 m, the largest step of its task). Empty for a platform
// without one.
std::vector<double> task_space(const std::string& platform);

}  // namespace nlsoft::console
