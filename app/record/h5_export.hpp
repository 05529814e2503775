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

// Writes every run of `ids` (each must exist: a missing one is a CliError
// before anything is written) to `path`, a regular file written beside its
// real path and renamed into place, so a failed export leaves nothing
// behind. Devices, FIFOs and standard output are refused: HDF5 seeks.
// Returns the samples written.
uint64_t export_runs_h5(RunStore& store, const std::vector<int64_t>& ids, const std::string& path);

}  // namespace nlsoft::console
