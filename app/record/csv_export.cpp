#include "app/record/csv_export.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>

#include "host/files/cli_error.hpp"
#include "host/files/output_file.hpp"
#include "app/record/step_time.hpp"

namespace nlsoft::console {

using host::CliError;
using host::OutputFile;

namespace tf = protocol::telemetry_field;

size_t export_run_csv(RunStore& store, int64_t run_id, const std::string& path) {
  return export_runs_csv(store, {run_id}, path);
}

size_t export_runs_csv(RunStore& store, const std::vector<int64_t>& run_ids, const std::string& path) {
  if (run_ids.empty()) throw CliError("runs export: name at least one run");
  std::vector<RunRow> runs;
  for (int64_t id : run_ids) {
    runs.push_back(store.run(id));
    for (const RunRow& other : runs)
      if (other.id == id && &other != &runs.back()) throw CliError(fmt::format("runs export: run {} is named twice", id));
    const RunRow &a = runs.front(), &b = runs.back();
    if (b.n != a.n || b.m != a.m || b.w != a.w)
      throw CliError(fmt::format("runs export: run {} has n={} m={} w={}, run {} n={} m={} w={}: one CSV holds runs of "
                                 "one shape (export them apart, or as --h5)",
                                 id, b.n, b.m, b.w, a.id, a.n, a.m, a.w));
  }
  const bool several = runs.size() > 1;
  const int n = runs.front().n, m = runs.front().m, w = runs.front().w;
  // A rig with sensor chips recorded each step's health: its invalid
  // channels are left empty (the firmware sent no reading, not a 0) and two
  // columns more say which and how old the chips' samples were.
  std::vector<std::map<uint32_t, SensorHealthRecord>> health;
  bool have_health = false;
  for (const RunRow& run : runs) {
    health.push_back(store.sensor_health(run.id));
    have_health = have_health || !health.back().empty();
  }
  OutputFile f(path);
  std::string head = several ? "run,k,step,time_us" : "k,step,time_us";
  for (const char* v : {"y_ref", "y_hat", "y_true"})
    for (int i = 0; i < n; ++i) head += fmt::format(",{}{}", v, i);
  for (int i = 0; i < m; ++i) head += fmt::format(",u{}", i);
  head += ",cost,iterations,compute_us";
  // An identification run's sensors last, so the columns before keep their places.
  for (int i = 0; i < w; ++i) head += fmt::format(",l{}", i);
  if (have_health) head += ",l_invalid,l_age_ms";
  // The step time last, for the same reason: readers that count columns
  // (and `train --data`, which knows a run export by its first three) keep
  // finding theirs.
  head += ",t\n";
  std::fputs(head.c_str(), f.get());
  size_t rows = 0;
  fmt::memory_buffer line;
  auto opt_vec = [&](bool has, const float* v, int count) {
    for (int i = 0; i < count; ++i) {
      if (has) fmt::format_to(std::back_inserter(line), ",{:.9g}", v[i]);
      else line.push_back(',');
    }
  };
  for (size_t r = 0; r < runs.size(); ++r) {
    const RunRow& run = runs[r];
    StepClock clock(run.loop_rate_hz);
    store.for_each_sample(run.id, [&](const Sample& s) {
      line.clear();
      if (several) fmt::format_to(std::back_inserter(line), "{},", run.id);
      fmt::format_to(std::back_inserter(line), "{},", s.k);
      if (s.has(tf::kStep)) fmt::format_to(std::back_inserter(line), "{}", s.step);
      line.push_back(',');
      if (s.has(tf::kTime)) fmt::format_to(std::back_inserter(line), "{}", s.time_us);
      opt_vec(s.has(tf::kYRef), s.y_ref(), n);
      opt_vec(s.has(tf::kYHat), s.y_hat(), n);
      opt_vec(s.has(tf::kYTrue), s.y_true(), n);
      opt_vec(s.has(tf::kU), s.u(), m);
      if (s.has(tf::kCost)) fmt::format_to(std::back_inserter(line), ",{:.9g}", s.cost);
      else line.push_back(',');
      if (s.has(tf::kSolver)) fmt::format_to(std::back_inserter(line), ",{},{:.9g}", s.iterations, s.compute_us);
      else line.append(std::string_view(",,"));
      const auto h = s.has(tf::kStep) ? health[r].find(s.step) : health[r].end();
      const uint32_t invalid = h == health[r].end() ? 0 : h->second.invalid;
      for (int i = 0; i < w; ++i) {
        if (s.w > 0 && !channel_invalid(invalid, size_t(i))) fmt::format_to(std::back_inserter(line), ",{:.9g}", s.l[i]);
        else line.push_back(',');
      }
      if (have_health) {
        if (h != health[r].end()) fmt::format_to(std::back_inserter(line), ",{},{}", h->second.invalid, h->second.age_ms);
        else line.append(std::string_view(",,"));
      }
      // Shortest digits that read back as the same double: t of a row is
      // exactly (step - first step) / loop_rate_hz.
      const double t = clock.at(s.has(tf::kStep), s.step);
      if (std::isnan(t)) line.push_back(',');
      else fmt::format_to(std::back_inserter(line), ",{}", t);
      line.push_back('\n');
      std::fwrite(line.data(), 1, line.size(), f.get());
      ++rows;
    });
  }
  f.commit();
  return rows;
}

}  // namespace nlsoft::console
