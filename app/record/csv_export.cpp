#include "app/record/csv_export.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "app/cli_error.hpp"
#include "app/output_file.hpp"

namespace nlsoft::console {

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
    if (runs.back().n != runs.front().n || runs.back().m != runs.front().m)
      throw CliError(fmt::format("runs export: run {} has n={} m={}, run {} n={} m={}: one CSV holds runs of one shape "
                                 "(export them apart, or as --h5)",
                                 id, runs.back().n, runs.back().m, runs.front().id, runs.front().n, runs.front().m));
  }
  const bool several = runs.size() > 1;
  const int n = runs.front().n, m = runs.front().m;
  OutputFile f(path);
  std::string head = several ? "run,k,step,time_us" : "k,step,time_us";
  for (const char* v : {"y_ref", "y_hat", "y_true"})
    for (int i = 0; i < n; ++i) head += fmt::format(",{}{}", v, i);
  for (int i = 0; i < m; ++i) head += fmt::format(",u{}", i);
  head += ",cost,iterations,compute_us\n";
  std::fputs(head.c_str(), f.get());
  size_t rows = 0;
  fmt::memory_buffer line;
  auto opt_vec = [&](bool has, const float* v, int count) {
    for (int i = 0; i < count; ++i) {
      if (has) fmt::format_to(std::back_inserter(line), ",{:.9g}", v[i]);
      else line.push_back(',');
    }
  };
  for (const RunRow& run : runs) {
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
      line.push_back('\n');
      std::fwrite(line.data(), 1, line.size(), f.get());
      ++rows;
    });
  }
  f.commit();
  return rows;
}

}  // namespace nlsoft::console
