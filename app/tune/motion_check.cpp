#include "app/tune/motion_check.hpp"

#include <fmt/format.h>

namespace nlsoft::console {

std::string still_reference_warning(const RunMetrics& m, const std::vector<double>& task, double settle_s,
                                    double window_s) {
  const TrackingMetrics& t = m.has_true ? m.truth : m.predicted;
  if (m.ref_span.empty()) return "";
  std::vector<int> axes = t.tracked;
  if (axes.empty())
    for (int a = 0; a < int(m.ref_span.size()); ++a) axes.push_back(a);
  // The axis on which the reference moves most, against the space it could.
  int best = -1;
  double share = -1;
  for (int a : axes) {
    if (a < 0 || size_t(a) >= m.ref_span.size()) continue;
    const double s = size_t(a) < task.size() && task[size_t(a)] > 0 ? m.ref_span[size_t(a)] / task[size_t(a)]
                                                                     : (m.ref_span[size_t(a)] > 0 ? 1.0 : 0.0);
    if (s > share) share = s, best = a;
  }
  if (best < 0 || share >= kStillReferenceShare) return "";
  const size_t b = size_t(best);
  const std::string against =
      b < task.size() ? fmt::format(" of the {:.3g} the rig's task space spans on y{} ({:.1f} %)", task[b], best, 100 * share)
                      : fmt::format(" on y{}", best);
  const std::string output = b < m.y_span.size() ? fmt::format(", while the output spans {:.3g}", m.y_span[b]) : "";
  return fmt::format(
      "warning: the reference barely moves in the scored window ({:g} s to {:g} s of each run): it spans {:.3g}{}{}; "
      "nrmse divides by that range, so this session scores noise. Score a window over the motion: a reference that "
      "moves in it (--reference \"swirl hold=1\"; reference=\"swirl hold=1\" in a script), a shorter --settle, or a "
      "longer --window (at hold=1 the whole Swirl takes 9.5 s at 130 Hz)",
      settle_s, settle_s + window_s, m.ref_span[b], against, output);
}

}  // namespace nlsoft::console
