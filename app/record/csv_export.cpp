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
  const RunRow run = store.run(run_id);
  OutputFile f(path);
  std::string head = "k,step,time_us";
  for (const char* v : {"y_ref", "y_hat", "y_true"})
    for (int i = 0; i < run.n; ++i) head += fmt::format(",{}{}", v, i);
  for (int i = 0; i < run.m; ++i) head += fmt::format(",u{}", i);
  head += ",cost,iterations,compute_us";
  // An identification run's sensors last, so the columns before keep their places.
  for (int i = 0; i < run.w; ++i) head += fmt::format(",l{}", i);
  head += '\n';
  std::fputs(head.c_str(), f.get());
  size_t rows = 0;
  fmt::memory_buffer line;
  auto opt_vec = [&](bool has, const float* v, int count) {
    for (int i = 0; i < count; ++i) {
      if (has) fmt::format_to(std::back_inserter(line), ",{:.9g}", v[i]);
      else line.push_back(',');
    }
  };
  store.for_each_sample(run_id, [&](const Sample& s) {
    line.clear();
    fmt::format_to(std::back_inserter(line), "{},", s.k);
    if (s.has(tf::kStep)) fmt::format_to(std::back_inserter(line), "{}", s.step);
    line.push_back(',');
    if (s.has(tf::kTime)) fmt::format_to(std::back_inserter(line), "{}", s.time_us);
    opt_vec(s.has(tf::kYRef), s.y_ref(), run.n);
    opt_vec(s.has(tf::kYHat), s.y_hat(), run.n);
    opt_vec(s.has(tf::kYTrue), s.y_true(), run.n);
    opt_vec(s.has(tf::kU), s.u(), run.m);
    if (s.has(tf::kCost)) fmt::format_to(std::back_inserter(line), ",{:.9g}", s.cost);
    else line.push_back(',');
    if (s.has(tf::kSolver)) fmt::format_to(std::back_inserter(line), ",{},{:.9g}", s.iterations, s.compute_us);
    else line.append(std::string_view(",,"));
    opt_vec(s.w > 0, s.l, run.w);
    line.push_back('\n');
    std::fwrite(line.data(), 1, line.size(), f.get());
    ++rows;
  });
  f.commit();
  return rows;
}

}  // namespace nlsoft::console
