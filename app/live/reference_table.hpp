#pragma once
// Reference tables: points read from a CSV file, packed into the transfer
// object of PROTOCOL.md 9.4 (kind 1).
#include <cstdint>
#include <string>
#include <vector>

namespace nlsoft::console {

struct ReferenceTablePoints {
  int n = 0;                // floats per point
  std::vector<float> rows;  // count x n
  size_t count() const { return n ? rows.size() / size_t(n) : 0; }
};

// One point per line, n comma-separated numbers; an optional header line of
// names and `#` comments are skipped. Throws CliError "file:line: ..." for a
// bad cell, a row of the wrong width, a non-finite value or an empty file.
ReferenceTablePoints read_reference_csv(const std::string& path, int n);

// format 1 | n | reserved u16 | count u32 | points f32 (little-endian).
std::vector<uint8_t> reference_table_object(const ReferenceTablePoints& t);

// The Swirl path (shared/reference.hpp) as table points: centre + scale * p.
ReferenceTablePoints swirl_table(const float centre[3], float scale, int n);
void write_reference_csv(const ReferenceTablePoints& t, const std::string& path);

}  // namespace nlsoft::console
