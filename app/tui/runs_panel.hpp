#pragma once
// The runs browser: recorded runs, newest first; Enter shows a run's
// metrics, m marks one and c compares the marked run with the selected one,
// e exports the selected run as CSV.
#include <mutex>
#include <string>
#include <vector>

#include "app/live/live_console.hpp"
#include "app/record/run_store.hpp"
#include "app/tui/ui.hpp"
#include "app/tui/worker.hpp"

namespace nlsoft::console::tui {

class RunsPanel {
 public:
  RunsPanel(LiveConsole& console, Worker& worker, Ui& ui) : console_(console), worker_(worker), ui_(ui) {}
  void reload();
  void draw(const Screen& screen, int y, int x, int h, int w, bool focused);
  bool key(int ch);

 private:
  void show(int64_t id);
  LiveConsole& console_;
  Worker& worker_;
  Ui& ui_;
  std::mutex mu_;
  std::vector<RunRow> runs_;
  std::vector<std::string> detail_;
  size_t selected_ = 0, top_ = 0;
  int64_t marked_ = 0;
};

}  // namespace nlsoft::console::tui
