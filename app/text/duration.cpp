#include "app/text/duration.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace nlsoft::console::text {

double parse_duration(const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str()) throw std::invalid_argument(fmt::format("'{}' is not a duration (e.g. 5s, 250ms, 2min)", text));
  const std::string unit = end;
  double scale = 0;
  if (unit == "s" || unit == "sec") scale = 1;
  else if (unit == "ms") scale = 1e-3;
  else if (unit == "min" || unit == "m") scale = 60;
  else if (unit == "h") scale = 3600;
  else if (unit.empty())
    throw std::invalid_argument(fmt::format("'{}' needs a unit: {}s, {}ms or {}min", text, text, text, text));
  else
    throw std::invalid_argument(fmt::format("'{}': unknown unit '{}' (use ms, s, min or h)", text, unit));
  if (!std::isfinite(v) || v <= 0) throw std::invalid_argument(fmt::format("'{}': a duration must be > 0", text));
  // Longer than any run or session: the step counts, clocks and budgets
  // computed from it would overflow.
  constexpr double kMaxDays = 30;
  if (v * scale > kMaxDays * 86400)
    throw std::invalid_argument(
        fmt::format("'{}': a duration is at most {:g} days ({:g}h)", text, kMaxDays, kMaxDays * 24));
  return v * scale;
}

}  // namespace nlsoft::console::text
