#pragma once
// Text from a user or a database (a run's label, a shared recording's
// notes, a cell of a CSV file quoted in an error) shown on a terminal: its
// control characters are written as escapes (\n, \t, \x1b, \u009b), so a
// label cannot move the cursor, recolour the screen or fake a line of
// output, and what is shown is what the bytes are.
#include <string>
#include <string_view>

namespace nlsoft::console {

std::string printable(std::string_view text);

// `text` cut to at most `max` characters (UTF-8 aware), "…" marking a cut,
// then made printable: for quoting a line of a file in a message.
std::string printable_excerpt(std::string_view text, size_t max = 80);

}  // namespace nlsoft::console
