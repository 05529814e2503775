#pragma once
// `--board NAME` checked against the board table (board_table.hpp): a name
// that is no board's, or a board that cannot do what the command does, is
// refused with the boards that can, each with its core.
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "host/rig/board_table.hpp"

namespace nlsoft::host {

// `allowed`: the boards the command takes (image_board_names(),
// qemu_board_names(), ...); `doing`: what it does with one, for the refusal.
inline CLI::Validator board_validator(const std::vector<std::string>& allowed, const std::string& doing) {
  return CLI::Validator(
      [allowed, doing](std::string& name) {
        const std::string why = board_refusal(name, allowed, doing);
        return why.empty() ? why : name + ": " + why;
      },
      "BOARD");
}

}  // namespace nlsoft::host
