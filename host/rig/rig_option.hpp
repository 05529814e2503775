#pragma once
// `--rig NAME|PATH`, the one option every command names a rig with, and
// `--platform`, its old spelling: still accepted for the scripts that use
// it, hidden from --help, and said to be deprecated on stderr (never on
// stdout, which may be JSON).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>

namespace nlsoft::host {

inline CLI::Option* add_rig_option(CLI::App* app, std::string& rig, const std::string& help) {
  CLI::Option* opt = app->add_option("--rig", rig, help)->type_name("NAME|PATH");
  // Checked here rather than with excludes(), which would print an empty
  // "Excludes:" under --rig in every --help (the hidden option's name).
  app->add_option_function<std::string>(
         "--platform",
         [&rig, opt](const std::string& v) {
           if (opt->count() > 0) throw CLI::ExcludesError("--platform", "--rig");
           std::fprintf(stderr, "nlsoft: --platform is deprecated; say --rig %s\n", v.c_str());
           rig = v;
         },
         "deprecated spelling of --rig")
      ->group("");
  return opt;
}

}  // namespace nlsoft::host
