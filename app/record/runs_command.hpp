#pragma once
// `nlsoft-console runs list|show|export|compare`: the recordings, offline.
#include <CLI/CLI.hpp>

namespace nlsoft::console {

void add_runs_command(CLI::App& app);

// `runs compare A B` (its table or --json; with svg or png, also drawn
// overlaid as `runs plot A B` draws them), for commands that make a run to
// set beside another (`runs replay`).
void compare_runs(const std::string& db, int64_t a, int64_t b, bool json, const std::string& svg = {},
                  const std::string& png = {});

}  // namespace nlsoft::console
