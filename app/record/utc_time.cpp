#include "app/record/utc_time.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <ctime>

namespace nlsoft::console {

std::string utc_now() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  tm t{};
  gmtime_r(&ts.tv_sec, &t);
  char buf[40];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S", &t);
  return fmt::format("{}.{:03d}Z", buf, int(ts.tv_nsec / 1000000));
}

std::optional<double> utc_seconds(const std::string& text) {
  tm t{};
  int ms = 0, used = 0;
  if (std::sscanf(text.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d.%3dZ%n", &t.tm_year, &t.tm_mon, &t.tm_mday, &t.tm_hour,
                  &t.tm_min, &t.tm_sec, &ms, &used) != 7 ||
      size_t(used) != text.size())
    return std::nullopt;
  t.tm_year -= 1900;
  t.tm_mon -= 1;
  return double(timegm(&t)) + ms * 1e-3;
}

}  // namespace nlsoft::console
