#pragma once
// `nlsoft-console flash --board stm32f4 --platform hasel [--hil]`: writes the
// built image to a Nucleo-64 through its ST-LINK with openocd, then opens the
// console on the board's virtual COM port.
#include <CLI/CLI.hpp>

namespace nlsoft::console {

void add_flash_command(CLI::App& app);

}  // namespace nlsoft::console
