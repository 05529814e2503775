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

// The names and units of a run's outputs, inputs and sensors when its rig is
// a shipped or installed one whose sizes match the run's (n, m, w); empty
// otherwise (a lab's own file is not known by name here). What `runs export
// --h5` writes beside the columns and `runs plot` labels its axes with.
struct RigColumns {
  std::vector<std::string> output_names, output_units, input_names, input_units, sensor_names, sensor_units;
};
RigColumns rig_columns(const std::string& platform, int n, int m, int w);

// "x (mm)": a name with its unit; `fallback` ("y0") where there is no name.
std::string axis_label(const std::vector<std::string>& names, const std::vector<std::string>& units, size_t i,
                       const std::string& fallback);

}  // namespace nlsoft::console
