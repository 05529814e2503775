#include "app/record/capture_csv.hpp"

#include <fmt/format.h>

#include <sstream>

#include "host/files/cli_error.hpp"
#include "host/files/input_file.hpp"
#include "app/model/csv.hpp"
#include "app/model/error.hpp"
#include "host/files/printable.hpp"

namespace nlsoft::console {

using host::CliError;
using host::InputKind;
using host::printable_excerpt;
using host::read_input_file;

namespace {

// A capture of hours at a few hundred Hz is tens of MB of text.
constexpr InputKind kCaptureCsv{"capture CSV", uint64_t(1) << 30};

bool blank(const std::string& s) { return s.find_first_not_of(" \t\r") == std::string::npos; }

std::string column_words(int n, const std::vector<std::string>& names) {
  std::string s = "time";
  for (int i = 0; i < n; ++i) {
    s += fmt::format(",y{}", i);
    if (size_t(i) < names.size() && !names[size_t(i)].empty()) s += fmt::format(" (or {})", names[size_t(i)]);
  }
  return s;
}

}  // namespace

Capture read_capture(const std::string& path, int n, const std::vector<std::string>& names) {
  const std::string text = read_input_file(path, kCaptureCsv);
  // parse_csv skips blank lines; the rows' own line numbers are kept here
  // so an error about a row (its time) can name its line.
  std::vector<long> lines;
  {
    std::istringstream in(text);
    std::string l;
    long no = 0;
    while (std::getline(in, l)) {
      ++no;
      if (!blank(l)) lines.push_back(no);
    }
  }
  model::Table table;
  try {
    std::istringstream in(text);
    table = model::parse_csv(in, path, true);
  } catch (const model::PipelineError& e) {
    throw CliError(e.what());
  }
  const long header_line = lines.empty() ? 1 : lines.front();
  const std::string expected = column_words(n, names);
  if (table.header.empty() || table.header[0] != "time")
    throw CliError(fmt::format("{}:{}: the first column must be 'time' (seconds on the capture's clock); the header "
                               "should read {}",
                               path, header_line, expected));
  // Which output each column holds.
  std::vector<int> output_of(table.header.size(), -1);
  std::vector<int> column_of(size_t(n), -1);
  for (size_t c = 1; c < table.header.size(); ++c) {
    const std::string& h = table.header[c];
    int which = -1;
    for (int i = 0; i < n && which < 0; ++i)
      if (h == fmt::format("y{}", i) || (size_t(i) < names.size() && h == names[size_t(i)])) which = i;
    if (which < 0)
      throw CliError(fmt::format("{}:{}: column {} ('{}') is no output of this run (n = {}); the header should read {}",
                                 path, header_line, c + 1, printable_excerpt(h), n, expected));
    if (column_of[size_t(which)] >= 0)
      throw CliError(fmt::format("{}:{}: columns {} and {} both hold output y{}", path, header_line,
                                 column_of[size_t(which)] + 1, c + 1, which));
    column_of[size_t(which)] = int(c);
    output_of[c] = which;
  }
  for (int i = 0; i < n; ++i)
    if (column_of[size_t(i)] < 0)
      throw CliError(fmt::format("{}:{}: no column for output y{}{}; the header should read {}", path, header_line, i,
                                 size_t(i) < names.size() ? fmt::format(" ({})", names[size_t(i)]) : "", expected));
  if (table.rows < 2) throw CliError(fmt::format("{}: {} data row: a capture needs at least two", path, table.rows));
  Capture cap;
  cap.path = path;
  cap.n = n;
  cap.t.reserve(size_t(table.rows));
  cap.y.resize(size_t(table.rows) * size_t(n));
  for (long r = 0; r < table.rows; ++r) {
    const long line = size_t(r) + 1 < lines.size() ? lines[size_t(r) + 1] : r + 2;
    const double t = table.at(r, 0);
    if (!cap.t.empty() && !(t > cap.t.back()))
      throw CliError(fmt::format("{}:{}: time {:.9g} s is not after the previous row's {:.9g} s (line {}): a capture's "
                                 "rows must be in strictly increasing time",
                                 path, line, t, cap.t.back(), cap.line.back()));
    cap.t.push_back(t);
    cap.line.push_back(line);
    for (int c = 1; c < table.cols; ++c) cap.y[size_t(r) * size_t(n) + size_t(output_of[size_t(c)])] = table.at(r, c);
  }
  return cap;
}

}  // namespace nlsoft::console
