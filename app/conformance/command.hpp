#pragma once
// `nlsoft-console conformance PORT|--sim PLATFORM|--qemu PLATFORM [--json]`:
// the protocol conformance suite (PROTOCOL.md) against any firmware.
// One line per check, `PASS|FAIL name: detail`, then `N passed, M failed`;
// exit 0 when all passed, 1 when one failed, 2 on a link error.
#include <CLI/CLI.hpp>

namespace nlsoft::console {

void add_conformance_command(CLI::App& app);

}  // namespace nlsoft::console
