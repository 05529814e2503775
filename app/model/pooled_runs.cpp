#include "app/model/pooled_runs.hpp"

#include "app/model/error.hpp"

namespace nlsoft::model {

Pooled pool_runs(const std::vector<Series>& runs, int nd, int dd, int folds, int validate) {
  struct Part {
    long begin, end;
  };
  std::vector<Dataset> sets;
  std::vector<Part> train_p, val_p, test_p;
  for (size_t i = 0; i < runs.size(); ++i) {
    sets.push_back(build_dataset(runs[i], nd, dd));
    const long rows = sets.back().rows();
    if (int(i) == validate) {
      train_p.push_back({0, 0});
      val_p.push_back({0, 0});
      test_p.push_back({0, rows});
      continue;
    }
    const long chunk = rows / (folds + 1);
    const std::string who = runs[i].name.empty() ? "the series" : runs[i].name;
    if (chunk < 1)
      throw PipelineError("too few rows (" + std::to_string(rows) + ") in " + who + " for " + std::to_string(folds) +
                          " folds");
    if (validate >= 0) {
      train_p.push_back({0, rows - chunk});
      val_p.push_back({rows - chunk, rows});
      test_p.push_back({rows, rows});
    } else {
      train_p.push_back({0, rows - 2 * chunk});
      val_p.push_back({rows - 2 * chunk, rows - chunk});
      test_p.push_back({rows - chunk, rows});
    }
  }
  Pooled out;
  Dataset& d = out.d;
  d.layout = sets.front().layout;
  long total = 0;
  for (const Dataset& s : sets) total += s.rows();
  d.X.resize(total, d.layout.p());
  d.Y.resize(total, d.layout.n);
  long at = 0;
  auto copy = [&](const std::vector<Part>& parts, bool test) {
    for (size_t i = 0; i < sets.size(); ++i) {
      const std::vector<RowRange> added = copy_rows(d, at, sets[i], parts[i].begin, parts[i].end);
      if (test) out.test_pieces.insert(out.test_pieces.end(), added.begin(), added.end());
      at += std::max(0L, parts[i].end - parts[i].begin);
    }
  };
  copy(train_p, false);
  out.split.train_end = at;
  out.split.val_begin = at;
  copy(val_p, false);
  out.split.val_end = at;
  out.split.test_begin = at;
  copy(test_p, true);
  out.split.test_end = at;
  const long test_rows = out.split.test_end - out.split.test_begin;
  if (validate >= 0) {
    out.held_out = runs[size_t(validate)].name + ", whole (" + std::to_string(test_rows) + " rows)";
  } else {
    out.held_out = "the last 1/" + std::to_string(folds + 1) + " of " +
                   (runs.size() == 1 ? std::string("the run") : "each of " + std::to_string(runs.size()) + " runs") +
                   " (" + std::to_string(test_rows) + " rows)";
  }
  return out;
}

}  // namespace nlsoft::model
