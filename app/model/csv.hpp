#pragma once
// Plain numeric CSV: comma separated, one record a line, an optional header
// line of column names. Every cell must be a finite number; the first bad
// cell is reported with file, line and column so a user can fix it.
#include <iosfwd>
#include <string>
#include <vector>

namespace nlsoft::model {

struct Table {
  std::vector<std::string> header;  // empty when read without a header
  int cols = 0;
  long rows = 0;
  std::vector<double> data;  // row-major, rows x cols
  std::vector<long> line;    // each row's line in the file, for messages
  double at(long r, int c) const { return data[static_cast<size_t>(r) * static_cast<size_t>(cols) + static_cast<size_t>(c)]; }
};

// Throws PipelineError. `name` is used in messages (usually the path).
// A UTF-8 byte order mark (spreadsheets write one) is no part of the first
// cell; two columns of one name, and a number beyond a float's range (the
// data are float32 measurements), are refused at their line.
// With empty_is_nan an empty cell reads as NaN (a field the row lacks, as
// `runs export` writes it); otherwise it is an error.
Table parse_csv(std::istream& in, const std::string& name, bool has_header, bool empty_is_nan = false);
Table read_csv(const std::string& path, bool has_header);

// `text` without a leading UTF-8 byte order mark.
std::string without_bom(std::string text);

// Writes with %.9g, enough to round-trip every float exactly.
void write_csv(std::ostream& out, const Table& t);

}  // namespace nlsoft::model
