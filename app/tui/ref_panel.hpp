#pragma once
// The reference panel: pick Infinity, Pringle, Diagonal, Swirl, Step or a CSV
// table, edit its parameters (preset for the connected rig to start with),
// and send it (`a`); a table upload shows a progress bar.
#include <atomic>
#include <mutex>
#include <string>
#include <vector>

#include "app/live/live_console.hpp"
#include "app/tui/line_edit.hpp"
#include "app/tui/ui.hpp"
#include "app/tui/worker.hpp"

namespace nlsoft::console::tui {

class RefPanel {
 public:
  RefPanel(LiveConsole& console, Worker& worker, Ui& ui);
  void draw(const Screen& screen, int y, int x, int h, int w, bool focused);
  bool key(int ch);
  bool editing() const { return edit_.active(); }
  // Selects the kind in force, with its parameters when this console sent
  // it; otherwise asks the firmware (worker) which kind it runs, with that
  // kind's preset. Called when the panel is opened (F3).
  void show_in_force();

 private:
  std::vector<std::string> keys() const;
  void reset_kind();
  void select_kind(size_t kind);
  void send();

  LiveConsole& console_;
  Worker& worker_;
  Ui& ui_;
  size_t kind_ = 0;  // index into kKinds
  size_t selected_ = 0;
  RefParams ref_{};
  std::string csv_path_ = "path.csv";
  uint16_t csv_hold_ = 1;
  LineEdit edit_;
  std::atomic<size_t> up_done_{0}, up_total_{0};
  std::atomic<bool> uploading_{false};
  // The firmware's own reference kind (kKinds index) read by the worker,
  // taken by the UI thread on its next draw or key; -1: none waiting.
  std::atomic<int> firmware_kind_{-1};
  std::atomic<int> firmware_ref_id_{-1};  // RefKind the firmware reported; -1: not asked / unknown
};

}  // namespace nlsoft::console::tui
