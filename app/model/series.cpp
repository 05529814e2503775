#include "app/model/series.hpp"

#include <cstdio>
#include <fstream>

#include "app/model/atomic_file.hpp"
#include "app/model/csv.hpp"
#include "app/model/error.hpp"

namespace nlsoft::model {

void Series::resize(long r, int m_, int n_, int w_) {
  m = m_;
  n = n_;
  w = w_;
  time.resize(r);
  u.resize(r, m_);
  y.resize(r, n_);
  l.resize(r, w_);
}

namespace {

// Counts the run of columns named prefix0, prefix1, ... starting at col.
int count_prefixed(const std::vector<std::string>& h, size_t col, char prefix) {
  int count = 0;
  while (col < h.size() && h[col] == std::string(1, prefix) + std::to_string(count)) {
    ++count;
    ++col;
  }
  return count;
}

std::string seconds(double t) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g s", t);
  return text;
}

Series from_table(const Table& t, const std::string& name) {
  const std::vector<std::string>& h = t.header;
  if (h.empty() || h[0] != "time")
    throw PipelineError(name + ": not training data: the header must start with 'time' (a dataset: time,u0..,y0..,"
                               "l0..) or with 'k,step,time_us' (a run, as `nlsoft-console runs export ID --csv` "
                               "writes it)");
  const int m = count_prefixed(h, 1, 'u');
  const int n = count_prefixed(h, 1 + size_t(m), 'y');
  const int w = count_prefixed(h, 1 + size_t(m + n), 'l');
  if (m == 0 || n == 0) throw PipelineError(name + ": the header needs at least one u column and one y column");
  if (1 + m + n + w != t.cols)
    throw PipelineError(name + ": unexpected column '" + h[size_t(1 + m + n + w)] +
                        "' (expected time,u0..,y0..,l0.. in that order)");
  Series s;
  s.resize(t.rows, m, n, w);
  s.name = name;
  for (long r = 0; r < t.rows; ++r) {
    s.time(r) = t.at(r, 0);
    if (r > 0 && !(s.time(r) > s.time(r - 1)))
      throw PipelineError(name + ":" + std::to_string(size_t(r) < t.line.size() ? t.line[size_t(r)] : r + 2) +
                          ": time " + seconds(s.time(r)) + " does not follow the previous row's " +
                          seconds(s.time(r - 1)) + ": time must increase");
    for (int i = 0; i < m; ++i) s.u(r, i) = t.at(r, 1 + i);
    for (int j = 0; j < n; ++j) s.y(r, j) = t.at(r, 1 + m + j);
    for (int i = 0; i < w; ++i) s.l(r, i) = t.at(r, 1 + m + n + i);
  }
  return s;
}

Table to_table(const Series& s) {
  Table t;
  t.header.push_back("time");
  for (int i = 0; i < s.m; ++i) t.header.push_back("u" + std::to_string(i));
  for (int j = 0; j < s.n; ++j) t.header.push_back("y" + std::to_string(j));
  for (int i = 0; i < s.w; ++i) t.header.push_back("l" + std::to_string(i));
  t.cols = static_cast<int>(t.header.size());
  t.rows = s.rows();
  t.data.reserve(static_cast<size_t>(t.rows) * static_cast<size_t>(t.cols));
  for (long r = 0; r < t.rows; ++r) {
    t.data.push_back(s.time(r));
    for (int i = 0; i < s.m; ++i) t.data.push_back(s.u(r, i));
    for (int j = 0; j < s.n; ++j) t.data.push_back(s.y(r, j));
    for (int i = 0; i < s.w; ++i) t.data.push_back(s.l(r, i));
  }
  return t;
}

}  // namespace

Series parse_series_csv(std::istream& in, const std::string& name) {
  return from_table(parse_csv(in, name, true), name);
}

Series read_series_csv(const std::string& path) { return from_table(read_csv(path, true), path); }

void write_series_csv(std::ostream& out, const Series& s) { write_csv(out, to_table(s)); }

void write_series_csv(const std::string& path, const Series& s) {
  const Table t = to_table(s);
  write_file_atomic(path, [&](std::ostream& out) { write_csv(out, t); });
}

}  // namespace nlsoft::model
