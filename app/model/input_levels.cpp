#include "app/model/input_levels.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace nlsoft::model {

std::vector<int> input_level_counts(const std::vector<Series>& runs) {
  int m = 0;
  for (const Series& s : runs) m = std::max(m, s.m);
  std::vector<int> counts(size_t(m), 0);
  for (int i = 0; i < m; ++i) {
    double seen[2] = {0.0, 0.0};
    int c = 0;
    for (const Series& s : runs) {
      if (i >= s.m) continue;
      for (long r = 0; r < s.rows() && c < 3; ++r) {
        const double v = s.u(r, i);
        if (std::find(seen, seen + c, v) != seen + c) continue;
        if (c < 2) seen[c] = v;
        ++c;
      }
    }
    counts[size_t(i)] = c;
  }
  return counts;
}

namespace {

// "u0", "u0 and u3", "u0, u1 and u3"
std::string input_list(const std::vector<int>& inputs) {
  std::string out;
  for (size_t k = 0; k < inputs.size(); ++k) {
    if (k > 0) out += k + 1 == inputs.size() ? " and " : ", ";
    out += "u" + std::to_string(inputs[k]);
  }
  return out;
}

}  // namespace

std::vector<std::string> input_level_notes(const std::vector<Series>& runs) {
  const std::vector<int> counts = input_level_counts(runs);
  std::vector<int> held, binary;
  for (size_t i = 0; i < counts.size(); ++i) {
    if (counts[i] == 1) held.push_back(int(i));
    if (counts[i] == 2) binary.push_back(int(i));
  }
  std::vector<std::string> notes;
  if (!held.empty())
    notes.push_back(fmt::format("note: {} held one value through every run: the model cannot learn what {} does",
                                input_list(held), held.size() == 1 ? "it" : "each"));
  if (!binary.empty()) {
    const char* them = binary.size() == 1 ? "it" : "them";
    notes.push_back(fmt::format(
        "note: {0} took two levels only (a binary signal, such as ident's prbs): the model never sees the inside of "
        "{1} range, where a controller following a path holds {2}; an aprbs run (ident's default) shows {2} every "
        "level (app/CONSOLE.md, \"Which signal to train from\")",
        input_list(binary), binary.size() == 1 ? "its" : "their", them));
  }
  return notes;
}

}  // namespace nlsoft::model
