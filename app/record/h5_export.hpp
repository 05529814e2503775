#pragma once
// Recorded runs as one HDF5 file, for MATLAB (h5read, h5info) and Python
// (h5py): a group /run_<id> per run holding its samples as datasets with
// their units, its setup as attributes, its gaps and parameter changes.
// The layout is documented in app/CONSOLE.md ("runs export --h5").
#include <cstdint>
#include <string>
#include <vector>

#include "app/record/run_store.hpp"

namespace nlsoft::console {

struct H5Export {
  uint64_t samples = 0;
  // One line for the user when some run's channels went without names and
  // units (its rig is in no rigs folder, or not of the run's sizes): "exported
  // without channel names and units: run 12's rig \"arm\" is in no rigs folder
  // (--rig FILE names them)". Empty when every run was named.
  std::string unnamed;
};

// Writes every run of `ids` (each must exist: a missing one is a CliError
// before anything is written) to `path`, built in memory and written whole
// through OutputFile, so a failed export leaves nothing behind. Each run's
// channels are named from `rig_arg` (--rig NAME|PATH) when given, which must
// be of every run's sizes (n and m, and w unless the run kept no sensors; a
// CliError naming both otherwise), else from the run's own rig when the
// console finds it by name (shipped, or in $NLSOFT_RIGS) and it is of the
// run's sizes.
H5Export export_runs_h5(RunStore& store, const std::vector<int64_t>& ids, const std::string& path,
                        const std::string& rig_arg = {});

}  // namespace nlsoft::console
