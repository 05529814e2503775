#include "app/live/reference_table.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "host/files/cli_error.hpp"
#include "host/files/input_file.hpp"
#include "host/files/printable.hpp"
#include "shared/reference.hpp"

namespace nlsoft::console {

using host::CliError;
using host::kReferenceCsv;
using host::printable_excerpt;
using host::read_input_file;

ReferenceTablePoints read_reference_csv(const std::string& path, int n) {
  std::istringstream in(read_input_file(path, kReferenceCsv));
  ReferenceTablePoints t;
  t.n = n;
  std::string line;
  int lineno = 0;
  bool first_data = true;
  while (std::getline(in, line)) {
    ++lineno;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const size_t start = line.find_first_not_of(" \t");
    if (start == std::string::npos || line[start] == '#') continue;
    std::vector<float> cells;
    bool numeric = true;
    size_t pos = 0;
    std::string bad;
    while (pos <= line.size()) {
      const size_t comma = line.find(',', pos);
      std::string cell = line.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
      pos = comma == std::string::npos ? line.size() + 1 : comma + 1;
      const size_t a = cell.find_first_not_of(" \t"), b = cell.find_last_not_of(" \t");
      cell = a == std::string::npos ? "" : cell.substr(a, b - a + 1);
      char* end = nullptr;
      const double v = std::strtod(cell.c_str(), &end);
      if (cell.empty() || *end != '\0') {
        numeric = false;
        if (bad.empty()) bad = cell;
        continue;
      }
      if (!std::isfinite(v)) throw CliError(fmt::format("{}:{}: '{}' is not a finite number", path, lineno, printable_excerpt(cell)));
      // The firmware holds a point as a float: beyond its range it would be inf there.
      if (!std::isfinite(float(v)))
        throw CliError(fmt::format("{}:{}: '{}' is beyond a float's range (+-{:g}) the firmware holds a point in",
                                   path, lineno, printable_excerpt(cell), double(std::numeric_limits<float>::max())));
      cells.push_back(float(v));
    }
    if (!numeric) {
      if (first_data) {
        first_data = false;  // a header of column names
        continue;
      }
      throw CliError(fmt::format("{}:{}: '{}' is not a number", path, lineno, printable_excerpt(bad)));
    }
    first_data = false;
    if (int(cells.size()) != n)
      throw CliError(fmt::format("{}:{}: {} value{} on this row, the firmware wants {} per point", path, lineno,
                                 cells.size(), cells.size() == 1 ? "" : "s", n));
    t.rows.insert(t.rows.end(), cells.begin(), cells.end());
  }
  if (t.rows.empty()) throw CliError(fmt::format("{}: no points", path));
  return t;
}

std::vector<uint8_t> reference_table_object(const ReferenceTablePoints& t) {
  std::vector<uint8_t> o(8 + 4 * t.rows.size());
  const uint32_t count = uint32_t(t.count());
  o[0] = 1;
  o[1] = uint8_t(t.n);
  o[2] = o[3] = 0;
  for (int i = 0; i < 4; ++i) o[size_t(4 + i)] = uint8_t(count >> (8 * i));
  for (size_t i = 0; i < t.rows.size(); ++i) {
    uint32_t bits;
    std::memcpy(&bits, &t.rows[i], 4);
    for (int b = 0; b < 4; ++b) o[8 + 4 * i + size_t(b)] = uint8_t(bits >> (8 * b));
  }
  return o;
}

ReferenceTablePoints swirl_table(const float centre[3], float scale, int n) {
  ReferenceTablePoints t;
  t.n = n;
  for (uint32_t i = 0; i < swirl::kPoints; ++i) {
    float p[3];
    swirl_point(i, p);
    for (int k = 0; k < n; ++k) t.rows.push_back(centre[k] + scale * p[k]);
  }
  return t;
}

void write_reference_csv(const ReferenceTablePoints& t, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw CliError(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
  for (int k = 0; k < t.n; ++k) out << (k ? "," : "") << "y" << k;
  out << "\n";
  for (size_t r = 0; r < t.count(); ++r) {
    for (int k = 0; k < t.n; ++k) out << (k ? "," : "") << fmt::format("{:.9g}", t.rows[r * size_t(t.n) + size_t(k)]);
    out << "\n";
  }
  if (!out) throw CliError(fmt::format("writing {} failed", path));
}

}  // namespace nlsoft::console
