#pragma once
// `runs merge-y ID FILE.csv [--offset S]` (and `ident --y-from FILE.csv`,
// which calls it once its run is recorded): an external measurement of the
// rig's outputs (motion capture) becomes the run's measured outputs, y_true,
// sample by sample. The capture's clock is placed on the run's (estimated,
// capture_offset.hpp, or given), the capture interpolated onto the run's
// samples and written in one transaction: the whole run or nothing.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace nlsoft::console {

struct MergeReport {
  double offset_s = 0;   // run time = capture time - offset_s
  bool estimated = false;
  double score = 0;      // the estimate's explained share (estimated only)
  size_t capture_rows = 0, rows_inside = 0;  // capture rows, and those inside the run's span
  size_t samples = 0, samples_set = 0;       // run samples, and those the capture covers
};

// Throws CliError (exit 2), the run unchanged: no such run, an unfinished
// one, a bad capture (capture_csv.hpp), no overlap. `names`: the rig's
// output names, accepted as column names besides y0, y1, ...
MergeReport merge_y(const std::string& db_path, int64_t run_id, const std::string& csv_path,
                    std::optional<double> offset_s, const std::vector<std::string>& names);

// "capture clock offset estimated: +1.234 s (run time = capture time -
// 1.234 s); 12,000 of 12,010 capture rows inside the run", then what was set.
std::string merge_words(int64_t run_id, const std::string& csv_path, const MergeReport& r);

}  // namespace nlsoft::console
