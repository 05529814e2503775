#include "app/model/csv.hpp"

#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <istream>
#include <ostream>

#include "app/model/atomic_file.hpp"
#include "app/model/error.hpp"
#include "host/files/printable.hpp"

namespace nlsoft::model {
namespace {

std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return s.substr(b, e - b);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  size_t start = 0;
  for (;;) {
    const size_t comma = line.find(',', start);
    cells.push_back(trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return cells;
}

bool blank(const std::string& line) { return trim(line).empty(); }

}  // namespace

std::string without_bom(std::string text) {
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);
  return text;
}

Table parse_csv(std::istream& in, const std::string& name, bool has_header, bool empty_is_nan) {
  Table t;
  std::string line;
  long lineno = 0;
  bool first = true;
  while (std::getline(in, line)) {
    ++lineno;
    if (lineno == 1) line = without_bom(line);
    if (blank(line)) continue;
    std::vector<std::string> cells = split(line);
    if (first && has_header) {
      const std::string at = name + ":" + std::to_string(lineno) + ": ";
      for (size_t c = 0; c < cells.size(); ++c) {
        if (cells[c].empty()) throw PipelineError(at + "empty column name in the header");
        for (size_t d = 0; d < c; ++d)
          if (cells[d] == cells[c])
            throw PipelineError(at + "columns " + std::to_string(d + 1) + " and " + std::to_string(c + 1) +
                                " are both named '" + host::printable_excerpt(cells[c]) + "'");
      }
      t.header = cells;
      t.cols = static_cast<int>(cells.size());
      first = false;
      continue;
    }
    if (first) t.cols = static_cast<int>(cells.size());
    first = false;
    if (static_cast<int>(cells.size()) != t.cols)
      throw PipelineError(name + ":" + std::to_string(lineno) + ": expected " + std::to_string(t.cols) +
                          " values, found " + std::to_string(cells.size()));
    for (size_t c = 0; c < cells.size(); ++c) {
      const std::string& cell = cells[c];
      if (cell.empty() && empty_is_nan) {
        t.data.push_back(std::nan(""));
        continue;
      }
      char* end = nullptr;
      errno = 0;
      const double v = cell.empty() ? 0.0 : std::strtod(cell.c_str(), &end);
      const std::string where = name + ":" + std::to_string(lineno) + ": column " + std::to_string(c + 1) +
                                (t.header.empty() ? std::string() : " ('" + host::printable_excerpt(t.header[c]) + "')");
      if (cell.empty() || end == nullptr || *end != '\0') throw PipelineError(where + ": not a number: '" + host::printable_excerpt(cell) + "'");
      if (!std::isfinite(v) || errno == ERANGE) throw PipelineError(where + ": not a finite number: '" + host::printable_excerpt(cell) + "'");
      if (std::fabs(v) > double(FLT_MAX)) {
        char most[32];
        std::snprintf(most, sizeof most, "%g", double(FLT_MAX));
        throw PipelineError(where + ": '" + host::printable_excerpt(cell) + "' is beyond a float's range (+-" +
                            most + "), where every measurement is kept");
      }
      t.data.push_back(v);
    }
    t.line.push_back(lineno);
    ++t.rows;
  }
  if (in.bad()) throw PipelineError("cannot read '" + name + "'");
  if (t.rows == 0) throw PipelineError(name + ": no data rows");
  return t;
}

Table read_csv(const std::string& path, bool has_header) {
  // A dataset of a million rows is ~200 MB of text; a bound far above that
  // still stops /dev/zero or a runaway generator before memory runs out.
  std::istringstream in(read_text_file(path, {"CSV file", uint64_t(1) << 30}));
  return parse_csv(in, path, has_header);
}

void write_csv(std::ostream& out, const Table& t) {
  for (size_t c = 0; c < t.header.size(); ++c) out << (c ? "," : "") << t.header[c];
  if (!t.header.empty()) out << '\n';
  char buf[40];
  for (long r = 0; r < t.rows; ++r) {
    for (int c = 0; c < t.cols; ++c) {
      std::snprintf(buf, sizeof buf, "%.9g", t.at(r, c));
      if (c) out << ',';
      out << buf;
    }
    out << '\n';
  }
}

}  // namespace nlsoft::model
