#pragma once
// Text from outside the console (a run's label, a shared recording's
// notes, a cell of a CSV file quoted in an error, and everything a firmware
// sends: LOG lines, its name, parameter names and units) shown on a
// terminal or written to a text file: the one escaping function for all of
// it. Control characters are written as escapes (\n, \t, \x1b), the C1
// controls and the bidirectional overrides and isolates as \u009b, \u202e,
// bytes that are not UTF-8 (a raw 0x9b among them) as \x9b, so a text cannot
// move the cursor, recolour the screen, set the clipboard or the title,
// reorder a line or fake a line of output, and what is shown is what the
// bytes are.
#include <string>
#include <string_view>

namespace nlsoft::host {

std::string printable(std::string_view text);

// `text` cut to at most `max` characters (UTF-8 aware), "…" marking a cut,
// then made printable: for quoting a line of a file in a message.
std::string printable_excerpt(std::string_view text, size_t max = 80);

// printable(text) in at most max_bytes bytes, "…" marking a cut (never
// inside a character): for a field of fixed size.
std::string printable_within(std::string_view text, size_t max_bytes);
// The NUL-terminated raw text made printable into out[capacity] (the same
// cut): a message's text field made safe where it is decoded.
void printable_into(const char* raw, char* out, size_t capacity);

}  // namespace nlsoft::host
