// The model subcommands alone, as nlsoft-console runs them, so the CLI tests
// do not depend on the rest of the console.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "app/model/commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"nlsoft model pipeline (test driver)"};
  app.require_subcommand(1);
  nlsoft::console::add_dataset_command(app);
  nlsoft::console::add_train_command(app);
  nlsoft::console::add_model_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
