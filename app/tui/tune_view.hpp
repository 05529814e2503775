#pragma once
// The TUI's convergence view of a `:tune` session: objective per evaluation
// and the best so far, under the live plot. The worker thread that runs the
// session adds evaluations; the UI thread draws a copy.
#include <mutex>
#include <string>
#include <vector>

#include "app/tui/screen.hpp"
#include "app/tune/tuner.hpp"

namespace nlsoft::console::tui {

class TuneTrace {
 public:
  // Any thread. An evaluation numbered 1 starts a new session's trace.
  void add(const TuneEvaluation& e);
  std::vector<TuneEvaluation> snapshot() const;
  bool empty() const;

 private:
  mutable std::mutex mu_;
  std::vector<TuneEvaluation> evals_;
};

// Draws into h rows from (y, x): a headline (evaluation, best, its
// parameters), the objective (dots) and best so far (line) against the
// evaluation; failed evaluations as marks on the bottom row.
void draw_tune_view(const Screen& screen, int y, int x, int h, int w, const std::vector<TuneEvaluation>& evals);

}  // namespace nlsoft::console::tui
