#pragma once
// The parameter panel, built from the firmware's PARAM_LIST: every value in
// force, edited in place (Enter), each edit shown pending -> applied (the
// value the firmware echoed) or refused (its reason); u undoes the last
// applied edit; S saves the set to a file, L loads one after showing the diff;
// after a firmware reset the rows it changed are marked and A re-applies.
// Below the list, the selected parameter explains itself: what it does, its
// range and unit (or its options), and the whole of a refusal.
#include <mutex>
#include <string>
#include <vector>

#include "app/link/param_catalog.hpp"
#include "app/live/live_console.hpp"
#include "app/tui/line_edit.hpp"
#include "app/tui/ui.hpp"
#include "app/tui/worker.hpp"

namespace nlsoft::console::tui {

class ParamPanel {
 public:
  ParamPanel(LiveConsole& console, Worker& worker, Ui& ui) : console_(console), worker_(worker), ui_(ui) {}

  void reload();  // fetches every value (worker)
  // After the firmware reset: fetches every value and marks the rows the
  // reset changed, so no old value stays on screen as if it were in force;
  // A sends the session's edits again.
  void reload_after_reset();
  void draw(const Screen& screen, int y, int x, int h, int w, bool focused);
  bool key(int ch);  // true if consumed
  bool editing() const { return edit_.active(); }

 private:
  // Unconfirmed: no reply (a timeout, the link down): the firmware may or
  // may not have taken the value, so it is not called a refusal.
  enum class State { Idle, Pending, Applied, Refused, Unconfirmed, Reset };
  struct Row {
    ParamInfo info;
    std::vector<double> value;
    State state = State::Idle;
    std::string note;  // refusal reason, or what was sent while pending
  };
  void draw_details(const Screen& screen, const Row& r, int y, int x, int h, int w);
  void send(size_t row, const std::vector<double>& values, bool record_undo);
  void fetch(bool after_reset);
  void reapply();
  void save();
  void load();

  LiveConsole& console_;
  Worker& worker_;
  Ui& ui_;
  std::mutex mu_;  // rows are written by the worker
  std::vector<Row> rows_;
  std::vector<std::pair<size_t, std::vector<double>>> undo_;
  size_t selected_ = 0, top_ = 0;
  LineEdit edit_;
  std::string loading_error_;
};

}  // namespace nlsoft::console::tui
