#include "app/tui/tui_app.hpp"

#include "app/cli_error.hpp"

namespace nlsoft::console {

int run_tui(LiveConsole&) { throw CliError("the TUI is not built yet; use --script"); }

}  // namespace nlsoft::console
