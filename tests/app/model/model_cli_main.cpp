// The model subcommands alone, as nlsoft-console runs them, so the CLI tests
// do not depend on the rest of the console.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "app/model/commands.hpp"
#include "host/rig/rig_catalog.hpp"
#include "app/rig/rig_pipeline.hpp"

int main(int argc, char** argv) {
  CLI::App app{"nlsoft model pipeline (test driver)"};
  app.require_subcommand(1);
  using namespace nlsoft::console;
  using nlsoft::host::rig_name_of_platform;
  add_dataset_command(app, rig_target_arg);
  add_train_command(app, rig_target_arg);
  add_model_command(app, rig_target_arg, rig_name_of_platform);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // a usage error is exit 2, as nlsoft-console says it
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
