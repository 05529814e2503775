#pragma once
// The recording's time stamps: UTC as ISO 8601 text with milliseconds,
// "2024-05-01T12:34:56.789Z", which sorts as text and reads in sqlite3.
#include <optional>
#include <string>

namespace nlsoft::console {

std::string utc_now();

// Seconds since the epoch of a utc_now() text; nullopt if it is not one.
std::optional<double> utc_seconds(const std::string& text);

}  // namespace nlsoft::console
