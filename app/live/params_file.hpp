#pragma once
// A parameter file as `params save` writes it (the header naming the
// firmware, one parameter a line, `params load` reads it back): one writer
// for the live console's save and for sets found where no firmware is
// connected (tune --replay's best, run on the simulator in this process).
#include <string>
#include <utility>
#include <vector>

#include "app/link/param_catalog.hpp"
#include "protocol/messages.hpp"

namespace nlsoft::console {

// Writes every parameter of `all` to `path`, all or nothing (a name that
// would not read back as one word is refused before a byte is written).
// Throws CliError.
void write_params_file(const std::string& path, const protocol::Info& firmware,
                       const std::vector<std::pair<ParamInfo, std::vector<double>>>& all);

}  // namespace nlsoft::console
