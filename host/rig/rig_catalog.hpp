#pragma once
// Rigs by name or path: `--rig NAME` is the shipped rigs folder's
// NAME.toml (host/paths: $NLSOFT_RIGS, the build tree, the install prefix),
// `--rig my.toml` or `--rig ./lab/arm.toml` a file.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "host/rig/rig.hpp"

namespace nlsoft::host {

// The shipped rigs' names, sorted; empty when the folder is missing.
std::vector<std::string> rig_names();

// A file for `arg`: a path when it names one (holds '/' or ends in .toml),
// else the rigs folder's <arg>.toml. Throws CliError (exit 2) listing the
// names, or the folders looked in.
std::string rig_path(const std::string& arg);
// How many times this process has called rig_path (a test counts them).
long rig_args_resolved();

// rig_path then load_rig; a bad file is a CliError with the loader's
// file:line message.
Rig load_rig_arg(const std::string& arg);

// The shipped rig whose file gives `info_platform` this number (what a
// firmware's INFO or a model file carries); empty when none does.
std::string rig_name_of_platform(uint8_t info_platform);

// For CLI options taking NAME|PATH: refuses what rig_path refuses, with its
// message, before the command runs.
CLI::Validator rig_arg_validator();

// "NAME|PATH (the shipped rigs' names)" for option help.
std::string rig_arg_help();

}  // namespace nlsoft::host
