// The one reader of rig files: TOML in, a validated Rig out. The only file
// that includes toml++; every error names the file, the line and the key.
#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "host/files/cli_error.hpp"
#include "host/files/input_file.hpp"
#include "host/files/printable.hpp"
#include "host/rig/board_pins.hpp"
#include "host/rig/rig.hpp"
#include "shared/activation.hpp"
#include "shared/chips/catalog.hpp"
#include "shared/crc32.hpp"
#include "shared/pid.hpp"
#include "shared/platform_id.hpp"
#include "shared/rig_config.hpp"
#include "shared/sim_plant.hpp"

namespace nlsoft::host {

namespace {

std::string join(const std::vector<std::string>& items) {
  std::string s;
  for (const std::string& i : items) s += (s.empty() ? "" : ", ") + i;
  return s;
}

// Shortest text that reads back as the same double (errors quote values).
std::string num(double v) {
  std::ostringstream o;
  o.precision(15);
  o << v;
  return o.str();
}

// A float bound as the parameter table states it (1e+12, not 999999995904).
std::string num(float v) {
  std::ostringstream o;
  o.precision(7);
  o << v;
  return o.str();
}

int line_of(const toml::node& n) { return int(n.source().begin.line); }

const char* type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::array: return "an array";
    case toml::node_type::table: return "a table";
    default: return "a date or time";
  }
}

// One table of the file and where it is, with typed getters. Every key it
// holds must be one of `known` (a misspelt key is an error, not ignored).
class Section {
 public:
  Section(const std::string& file, const toml::table& t, std::string where, int line,
          std::vector<std::string> known)
      : file_(file), t_(t), where_(std::move(where)), line_(line), known_(std::move(known)) {
    for (const auto& [k, v] : t_) {
      bool ok = false;
      for (const std::string& n : known_) ok = ok || n == k.str();
      if (!ok)
        fail(line_of(v), std::string(k.str()),
             std::string("unknown ") + (v.is_table() || v.is_array_of_tables() ? "table" : "key") +
                 " (known: " + join(known_) + ")");
    }
  }

  [[noreturn]] void fail(int line, const std::string& key, const std::string& what) const {
    const std::string label = where_.empty() ? key : (key.empty() ? where_ : where_ + " " + key);
    throw RigError(file_ + ":" + std::to_string(line) + ": " + label + ": " + what, file_, line, key);
  }

  bool has(const std::string& key) const { return t_.contains(key); }
  int line() const { return line_; }
  int line(const std::string& key) const {
    const toml::node* n = t_.get(key);
    return n ? line_of(*n) : line_;
  }
  const std::string& where() const { return where_; }

  const toml::node& node(const std::string& key) const {
    const toml::node* n = t_.get(key);
    if (!n) fail(line_, key, "missing key");
    return *n;
  }

  // Any number as written (integers too), finite or not: the controller's
  // defaults go to the parameter checks as they are.
  double raw_number(const std::string& key) const { return as_number(node(key), key); }

  double number(const std::string& key) const {
    const double v = raw_number(key);
    if (!std::isfinite(v)) fail(line(key), key, "must be finite, not " + num(v));
    return v;
  }
  double number(const std::string& key, double fallback) const { return has(key) ? number(key) : fallback; }
  double positive(const std::string& key) const {
    const double v = number(key);
    if (!(v > 0)) fail(line(key), key, "must be > 0, not " + num(v));
    return v;
  }

  long long integer(const std::string& key, long long lo, long long hi, const std::string& why = "") const {
    const toml::node& n = node(key);
    if (!n.is_integer()) fail(line_of(n), key, std::string("expected an integer, got ") + type_name(n));
    const long long v = n.as_integer()->get();
    if (v < lo || v > hi)
      fail(line_of(n), key, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]" + why +
                                 ", not " + std::to_string(v));
    return v;
  }

  std::string text(const std::string& key) const {
    const toml::node& n = node(key);
    if (!n.is_string()) fail(line_of(n), key, std::string("expected a string, got ") + type_name(n));
    return n.as_string()->get();
  }
  std::string text(const std::string& key, const std::string& fallback) const {
    return has(key) ? text(key) : fallback;
  }
  // Text shown on one line (a unit, a description): no control characters,
  // so a newline cannot start a line of its own where the text is printed.
  // The C1 controls (U+0080..U+009F: U+009B starts an escape sequence as
  // ESC [ does) and the bidirectional controls (U+202E shows the rest of a
  // line backwards) are refused with the C0 ones: each makes what a
  // terminal shows differ from what the file says.
  std::string line_text(const std::string& key, const std::string& fallback) const {
    const std::string v = text(key, fallback);
    for (size_t i = 0; i < v.size(); ++i) {
      const auto b = [&](size_t j) { return j < v.size() ? static_cast<unsigned char>(v[j]) : 0u; };
      if (b(i) < 0x20 || b(i) == 0x7f)
        fail(line(key), key, fmt::format("holds the control character 0x{:02x}: one line of text, please", b(i)));
      if (b(i) == 0xc2 && b(i + 1) >= 0x80 && b(i + 1) <= 0x9f)
        fail(line(key), key, fmt::format("holds the control character U+{:04X}: one line of text, please", b(i + 1)));
      const unsigned cp3 = b(i) == 0xe2 || b(i) == 0xd8 ? (b(i) << 16 | b(i + 1) << 8 | b(i + 2)) : 0;
      const unsigned cp2 = b(i) == 0xd8 ? (b(i) << 8 | b(i + 1)) : 0;
      const bool bidi = cp2 == 0xd89c ||                          // U+061C arabic letter mark
                        cp3 == 0xe2808e || cp3 == 0xe2808f ||     // U+200E, U+200F
                        (cp3 >= 0xe280aa && cp3 <= 0xe280ae) ||   // U+202A..U+202E
                        (cp3 >= 0xe281a6 && cp3 <= 0xe281a9);     // U+2066..U+2069
      if (bidi)
        fail(line(key), key,
             fmt::format("holds a bidirectional control ({}), which reorders how the line reads: plain text, please",
                         printable(v.substr(i, cp2 ? 2 : 3))));
    }
    return v;
  }
  // One of `names`; the error lists them.
  std::string choice(const std::string& key, const std::vector<std::string>& names) const {
    const std::string v = text(key);
    for (const std::string& n : names)
      if (n == v) return v;
    fail(line(key), key, "'" + printable_excerpt(v, 40) + "' is not one of: " + join(names));
  }
  // The value `key` names among `values`; the error lists the names.
  template <class E>
  E choice(const std::string& key, const std::vector<std::pair<std::string, E>>& values) const {
    std::vector<std::string> names;
    for (const auto& v : values) names.push_back(v.first);
    const std::string v = choice(key, names);
    for (const auto& c : values)
      if (c.first == v) return c.second;
    fail(line(key), key, "'" + v + "' has no value");  // unreachable: choice() refused it
  }

  const toml::array& array(const std::string& key) const {
    const toml::node& n = node(key);
    if (!n.is_array()) fail(line_of(n), key, std::string("expected an array, got ") + type_name(n));
    return *n.as_array();
  }
  // An array of numbers; `finite`: each must be.
  std::vector<double> numbers(const std::string& key, bool finite = true) const {
    std::vector<double> out;
    const toml::array& a = array(key);
    for (size_t i = 0; i < a.size(); ++i) {
      const std::string at = key + "[" + std::to_string(i) + "]";
      const double v = as_number(a[i], at);
      if (finite && !std::isfinite(v)) fail(line_of(a[i]), at, "must be finite, not " + num(v));
      out.push_back(v);
    }
    return out;
  }
  std::array<double, 3> triple(const std::string& key) const {
    const std::vector<double> v = numbers(key);
    if (v.size() != 3) fail(line(key), key, "expected 3 numbers, got " + std::to_string(v.size()));
    return {v[0], v[1], v[2]};
  }
  // How many of something a key must hold: "n = 2 rows (one per [[output]])".
  struct Count {
    std::string name;
    int value;
    std::string why;
    std::string text(const std::string& noun) const {
      return name + " = " + std::to_string(value) + " " + noun + " (" + why + ")";
    }
  };

  // An array of rows.value arrays of cols.value numbers each, every one
  // finite and within +-limit.
  std::vector<std::vector<double>> matrix(const std::string& key, const Count& rows, const Count& cols,
                                          double limit) const {
    const toml::array& a = array(key);
    if (a.size() != size_t(rows.value))
      fail(line(key), key, "expected " + rows.text("rows") + ", got " + std::to_string(a.size()));
    std::vector<std::vector<double>> out;
    for (size_t r = 0; r < a.size(); ++r) {
      const std::string at = key + "[" + std::to_string(r) + "]";
      if (!a[r].is_array()) fail(line_of(a[r]), at, std::string("expected an array (a row), got ") + type_name(a[r]));
      const toml::array& row = *a[r].as_array();
      if (row.size() != size_t(cols.value))
        fail(line_of(a[r]), at, "expected " + cols.text("numbers") + ", got " + std::to_string(row.size()));
      std::vector<double> v;
      for (size_t c = 0; c < row.size(); ++c) {
        const std::string at_c = at + "[" + std::to_string(c) + "]";
        const double x = as_number(row[c], at_c);
        if (!std::isfinite(x)) fail(line_of(row[c]), at_c, "must be finite, not " + num(x));
        if (std::fabs(x) > limit) fail(line_of(row[c]), at_c, "must be within +-" + num(limit) + ", not " + num(x));
        v.push_back(x);
      }
      out.push_back(v);
    }
    return out;
  }
  // An array of count.value finite numbers in [lo, hi].
  std::vector<double> vector(const std::string& key, const Count& count, double lo, double hi) const {
    const std::vector<double> v = numbers(key);
    if (v.size() != size_t(count.value))
      fail(line(key), key, "expected " + count.text("numbers") + ", got " + std::to_string(v.size()));
    for (size_t i = 0; i < v.size(); ++i)
      if (v[i] < lo || v[i] > hi)
        fail(element_line(key, int(i)), key + "[" + std::to_string(i) + "]",
             "must be in [" + num(lo) + ", " + num(hi) + "], not " + num(v[i]));
    return v;
  }
  // A finite number in [lo, hi]; `why` follows the bounds in the message.
  double bounded(const std::string& key, double lo, double hi, const std::string& why = "") const {
    const double v = number(key);
    if (v < lo || v > hi) fail(line(key), key, "must be in [" + num(lo) + ", " + num(hi) + "]" + why + ", not " + num(v));
    return v;
  }

  // Line of element i of an array key (arrays may span lines).
  int element_line(const std::string& key, int i) const {
    const toml::node* n = t_.get(key);
    if (n && n->is_array() && i >= 0 && size_t(i) < n->as_array()->size()) return line_of((*n->as_array())[size_t(i)]);
    return line(key);
  }

 private:
  double as_number(const toml::node& n, const std::string& key) const {
    if (n.is_integer()) return double(n.as_integer()->get());
    if (n.is_floating_point()) return n.as_floating_point()->get();
    fail(line_of(n), key, std::string("expected a number, got ") + type_name(n));
  }

  const std::string& file_;
  const toml::table& t_;
  std::string where_;
  int line_;
  std::vector<std::string> known_;
};

// Optional sub-table (`[controller]`) or nullptr.
const toml::table* sub_table(const Section& root, const toml::table& t, const std::string& key) {
  const toml::node* n = t.get(key);
  if (!n) return nullptr;
  if (!n->is_table()) root.fail(line_of(*n), key, std::string("expected a table [") + key + "], got " + type_name(*n));
  return n->as_table();
}

// The tables of `[[key]]`, each with its header line.
std::vector<const toml::table*> table_array(const Section& root, const toml::table& t, const std::string& key) {
  std::vector<const toml::table*> out;
  const toml::node* n = t.get(key);
  if (!n) return out;
  if (!n->is_array_of_tables())
    root.fail(line_of(*n), key, "expected tables [[" + key + "]], got " + type_name(*n));
  for (const toml::node& e : *n->as_array()) out.push_back(e.as_table());
  return out;
}

std::string nth(const std::string& table, size_t i) { return "[[" + table + "]] #" + std::to_string(i + 1); }

// Names label recorded columns, the console's plots and the generated
// image's source: one name, one thing, spelt as an identifier with '.' and
// '-' (the grammar docs/rig-file.md states), so it is data everywhere.
constexpr size_t kChannelNameMax = 32;
struct NameBook {
  std::map<std::string, std::pair<std::string, int>> seen;  // name -> (where, line)
  void add(const Section& s, const std::string& name) {
    const bool starts = !name.empty() && (std::isalpha(static_cast<unsigned char>(name[0])) || name[0] == '_');
    if (!starts || name.size() > kChannelNameMax ||
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-") !=
            std::string::npos)
      s.fail(s.line("name"), "name",
             fmt::format("{} is not a name: a letter or '_', then letters, digits, '_', '.' or '-', at most {} "
                         "characters",
                         "'" + printable_excerpt(name, 40) + "'", kChannelNameMax));
    const auto it = seen.find(name);
    if (it != seen.end())
      s.fail(s.line("name"), "name",
             "'" + name + "' is already the name of " + it->second.first + " (line " +
                 std::to_string(it->second.second) + ")");
    seen[name] = {s.where(), s.line("name")};
  }
};

int index_of(const std::vector<std::string>& names, const std::string& name) {
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return int(i);
  return -1;
}

// Pins and channels used once each, on a board that has them.
struct PinBook {
  const BoardPins* board = nullptr;
  std::string board_name;
  int board_line = 0;
  std::map<std::string, std::pair<std::string, int>> used;  // pin -> (where, line)

  void pwm(const Section& s, const std::string& pin) {
    const std::vector<std::string>& known = board->pwm;
    bool ok = false;
    for (const std::string& k : known) ok = ok || k == pin;
    if (!ok)
      s.fail(s.line("pwm"), "pwm",
             "unknown pin '" + printable_excerpt(pin, 40) + "' on board " + board_name + " (PWM pins: " + join(known) +
                 ")");
    take(s, "pwm", pin);
  }
  void adc(const Section& s, int channel) {
    bool ok = false;
    std::vector<std::string> known;
    for (int c : board->adc) {
      ok = ok || c == channel;
      known.push_back(std::to_string(c));
    }
    if (!ok)
      s.fail(s.line("adc"), "adc",
             "unknown pin: ADC1 channel " + std::to_string(channel) + " is not wired on board " + board_name +
                 " (channels: " + join(known) + ")");
    take(s, "adc", "ADC1 channel " + std::to_string(channel));
    // Its pin too: a bus may share it (SPI1's MISO and MOSI are ADC1_IN6/IN7's).
    for (size_t i = 0; i < board->adc.size() && i < board->adc_pins.size(); ++i)
      if (board->adc[i] == channel) take(s, "adc", board->adc_pins[i]);
  }
  void cs(const Section& s, const std::string& pin) {
    if (index_of(board->chip_selects, pin) < 0)
      s.fail(s.line("cs"), "cs",
             "unknown chip-select pin '" + printable_excerpt(pin, 40) + "' on board " + board_name +
                 " (chip-select pins: " + join(board->chip_selects) + ")");
    take(s, "cs", pin);
  }
  void take(const Section& s, const std::string& key, const std::string& pin) {
    const auto it = used.find(pin);
    if (it != used.end())
      s.fail(s.line(key), key,
             pin + " is already used by " + it->second.first + " (line " + std::to_string(it->second.second) + ")");
    used[pin] = {s.where(), s.line(key)};
  }
};

// Lines of each input's min and max, for the parameter checks' errors.
using LimitLines = std::vector<std::array<int, 2>>;

// The controller computes in float: a bound past a float's range, or a
// range whose width max - min is (1.7e308 - -1.7e308 = inf in double too),
// would make every span, step and normalisation from it infinite.
void refuse_infinite_range(const Section& s, double min, double max) {
  for (const auto& [key, v] : {std::pair<const char*, double>{"min", min}, {"max", max}})
    if (!(std::fabs(v) <= double(FLT_MAX)))
      s.fail(s.line(key), key, "must be a float (within +-" + num(double(FLT_MAX)) + "), not " + num(v));
  const double span = max - min;
  if (!(span <= double(FLT_MAX)))
    s.fail(s.line("max"), "max",
           "makes the span max - min = " + num(span) + ", not a float (at most " + num(double(FLT_MAX)) +
               "): narrow the range");
}

// An [[input]] or an [[output]]: a named channel in a unit, between a min
// and a max. Both are read, and refused, in the same words.
template <class Channel>
void read_name_and_range(const Section& s, NameBook& names, Channel& c) {
  c.name = s.text("name");
  names.add(s, c.name);
  c.unit = s.line_text("unit", "");
  c.min = s.number("min");
  c.max = s.number("max");
  if (!(c.min < c.max))
    s.fail(s.line("max"), "max", "must be > min (" + num(c.min) + " at line " + std::to_string(s.line("min")) + ")");
  refuse_infinite_range(s, c.min, c.max);
}

// An input's servo keys; the servo itself is found once the devices are read (link_servos).
void read_servo_keys(const Section& s, RigInput& in) {
  if (!s.has("servo")) {
    for (const char* k : {"goal_per_unit", "goal_at_neutral"})
      if (s.has(k)) s.fail(s.line(k), k, "only with servo = \"DEVICE\" (the input names no servo)");
    return;
  }
  if (s.has("pwm"))
    s.fail(s.line("servo"), "servo",
           "the input is on pwm = \"" + in.pwm + "\" (line " + std::to_string(s.line("pwm")) +
               "): a servo or a PWM pin drives it, not both");
  in.servo = s.text("servo");
  in.servo_line = s.line("servo");
  in.goal_per_unit = s.number("goal_per_unit");
  if (!(std::fabs(in.goal_per_unit) > 0.0) || !std::isfinite(in.goal_per_unit))
    s.fail(s.line("goal_per_unit"), "goal_per_unit", "must be a finite number other than 0 (goal steps per " +
                                                         (in.unit.empty() ? std::string("unit") : in.unit) + ")");
  in.goal_at_neutral = s.number("goal_at_neutral");
}

void read_inputs(const std::string& file, const Section& root, const toml::table& t, Rig& rig, NameBook& names,
                 PinBook& pins, LimitLines& lines) {
  const auto tables = table_array(root, t, "input");
  for (size_t i = 0; i < tables.size(); ++i) {
    const Section s(file, *tables[i], nth("input", i), line_of(*tables[i]),
                    {"name", "unit", "min", "max", "neutral", "pwm", "servo", "goal_per_unit", "goal_at_neutral"});
    if (i >= size_t(RigCapacity::m))
      s.fail(s.line(), "", "over capacity: at most m = " + std::to_string(RigCapacity::m) + " inputs");
    RigInput in;
    read_name_and_range(s, names, in);
    in.neutral = s.number("neutral");
    if (in.neutral < in.min || in.neutral > in.max)
      s.fail(s.line("neutral"), "neutral",
             "must lie in [min, max] = [" + num(in.min) + ", " + num(in.max) + "] (lines " +
                 std::to_string(s.line("min")) + ", " + std::to_string(s.line("max")) + "), not " + num(in.neutral));
    in.line = s.line();
    if (s.has("pwm")) {
      in.pwm = s.text("pwm");
      in.pwm_line = s.line("pwm");
      pins.pwm(s, in.pwm);
    }
    read_servo_keys(s, in);
    rig.inputs.push_back(in);
    lines.push_back({s.line("min"), s.line("max")});
  }
  if (rig.inputs.empty())
    root.fail(root.line(), "[[input]]", "none given: a rig drives 1 to " + std::to_string(RigCapacity::m) +
                                            " inputs (m = 0)");
}

// value = offset + gain * reading.
void read_scaling(const Section& s, double& gain, double& offset) {
  gain = s.number("gain", 1.0);
  if (gain == 0.0) s.fail(s.line("gain"), "gain", "must not be 0");
  offset = s.number("offset", 0.0);
}

// An ADC channel with its scaling: value = offset + gain * volts.
void read_adc(const Section& s, PinBook& pins, int& adc, double& gain, double& offset) {
  adc = int(s.integer("adc", 0, 31));
  pins.adc(s, adc);
  read_scaling(s, gain, offset);
}

// Keys a source does not have: each belongs to the sources `owners` names.
void refuse_keys(const Section& s, const std::string& source, const std::vector<std::string>& keys,
                 const std::string& owners) {
  for (const std::string& k : keys)
    if (s.has(k)) s.fail(s.line(k), k, "only with " + owners + " (source is \"" + source + "\" at line " +
                                          std::to_string(s.line("source")) + ")");
}
void refuse_adc_keys(const Section& s, const std::string& source) {
  refuse_keys(s, source, {"adc", "gain", "offset"}, "source = \"adc\"");
}

void read_outputs(const std::string& file, const Section& root, const toml::table& t, Rig& rig, NameBook& names,
                  PinBook& pins) {
  const auto tables = table_array(root, t, "output");
  for (size_t i = 0; i < tables.size(); ++i) {
    const Section s(file, *tables[i], nth("output", i), line_of(*tables[i]),
                    {"name", "unit", "min", "max", "span", "rest", "source", "adc", "gain", "offset"});
    if (i >= size_t(RigCapacity::n))
      s.fail(s.line(), "", "over capacity: at most n = " + std::to_string(RigCapacity::n) + " outputs");
    RigOutput out;
    read_name_and_range(s, names, out);
    out.span = s.has("span") ? s.positive("span") : out.max - out.min;
    if (!(out.span <= double(FLT_MAX)))
      s.fail(s.line("span"), "span", "must be a float (at most " + num(double(FLT_MAX)) + "), not " + num(out.span));
    out.rest = s.number("rest", 0.5 * (out.min + out.max));
    if (out.rest < out.min || out.rest > out.max)
      s.fail(s.line("rest"), "rest", "must be within min..max (" + num(out.min) + ".." + num(out.max) + ")");
    const std::string source = s.has("source") ? s.choice("source", {"none", "adc", "external"}) : "none";
    if (source == "adc") {
      out.source = OutputSource::Adc;
      out.adc_line = s.line("adc");
      read_adc(s, pins, out.adc, out.gain, out.offset);
    } else {
      out.source = source == "external" ? OutputSource::External : OutputSource::None;
      refuse_adc_keys(s, source);
    }
    rig.outputs.push_back(out);
  }
  if (rig.outputs.empty())
    root.fail(root.line(), "[[output]]", "none given: a rig controls 1 to " + std::to_string(RigCapacity::n) +
                                             " outputs (n = 0)");
}

// A [[device]]'s setting (range, rate): one the chip offers, or none when
// it has no such setting. The error lists what it offers.
void read_setting(const Section& s, const std::string& key, const chips::ChipSpec& chip,
                  const chips::Setting* settings, int count, const std::string& unit, double& value,
                  uint8_t& bits) {
  if (count == 0) {
    if (s.has(key)) s.fail(s.line(key), key, std::string("chip ") + chip.name + " has no " + key + " setting");
    return;
  }
  value = s.number(key);
  std::vector<std::string> offered;
  for (int i = 0; i < count; ++i) {
    if (float(value) == settings[i].value) {
      bits = settings[i].bits;
      return;
    }
    offered.push_back(num(settings[i].value));
  }
  s.fail(s.line(key), key,
         fmt::format("{} {} is not a {} chip {} offers ({}: {})", num(value), unit, key, chip.name, unit,
                     join(offered)));
}


void read_chip_clock(const Section& s, const PinBook& pins, const BoardBus& bus, RigDevice& d) {
    const chips::ChipSpec& chip = *d.chip;
    const bool i2c = d.kind == BusKind::I2c;
    // A chip on both buses states its SPI maximum; on I2C the bus's own bounds it.
    const bool chip_bound = !i2c || !chip.on_spi;
    // Standard-mode I2C and the paper's SPI clock, unless the chip is slower.
    const uint32_t fallback = std::min<uint32_t>(i2c ? 100000u : 1000000u, chip.max_clock_hz);
    d.clock_hz = s.has("clock_hz") ? uint32_t(s.integer("clock_hz", 1, 100000000, " Hz")) : fallback;
    if (chip_bound && d.clock_hz > chip.max_clock_hz)
      s.fail(s.line("clock_hz"), "clock_hz",
             fmt::format("{} Hz is above chip {}'s maximum, {} Hz", d.clock_hz, chip.name, chip.max_clock_hz));
    if (d.clock_hz > bus.max_clock_hz)
      s.fail(s.line("clock_hz"), "clock_hz",
             fmt::format("{} Hz is above bus {}'s maximum on board {}, {} Hz", d.clock_hz, d.bus, pins.board_name,
                         bus.max_clock_hz));
}

// A sensor chip's place on an I2C or SPI bus: its address or chip select.
void read_chip_address(const Section& s, PinBook& pins, const BoardBus& bus, RigDevice& d) {
  const chips::ChipSpec& chip = *d.chip;
  const bool i2c = bus.kind == BusKind::I2c;
  if (i2c ? !chip.on_i2c : !chip.on_spi)
    s.fail(s.line("bus"), "bus",
           fmt::format("{} is a{} bus, and chip {} talks {} only", d.bus, i2c ? "n I2C" : " SPI", chip.name,
                       i2c ? "SPI" : "I2C"));
  for (const char* k : {"baud", "on_fault"})
    if (s.has(k)) s.fail(s.line(k), k, "only for a servo on a serial bus (bus " + d.bus + " is not one)");
  const std::string bus_is = fmt::format("bus = \"{}\" (line {}) is {}", d.bus, s.line("bus"), i2c ? "I2C" : "SPI");
  if (i2c) {
    if (s.has("cs")) s.fail(s.line("cs"), "cs", "a chip select is for a SPI bus: " + bus_is + "; give address");
    // The 7-bit addresses I2C leaves to devices (0x00-0x07 and 0x78-0x7f are reserved).
    d.address = s.has("address") ? int(s.integer("address", 0x08, 0x77, " (a 7-bit I2C address)"))
                                 : chip.default_address;
    pins.take(s, "address", fmt::format("{} address 0x{:02x}", d.bus, d.address));
  } else if (bus.own_chip_select) {
    if (s.has("address")) s.fail(s.line("address"), "address", "an address is for an I2C bus: " + bus_is);
    if (s.has("cs"))
      s.fail(s.line("cs"), "cs", "bus " + d.bus + " selects its one chip itself (its own select line): no cs");
    pins.take(s, "bus", d.bus + "'s one chip");
  } else {
    if (s.has("address")) s.fail(s.line("address"), "address", "an address is for an I2C bus: " + bus_is + "; give cs");
    d.cs = s.text("cs");
    pins.cs(s, d.cs);
    d.cs_index = index_of(pins.board->chip_selects, d.cs);
  }
}

// A servo on a serial bus: its id (address), the bus's baud, what a fault does.
void read_servo_device(const Section& s, const Rig& rig, PinBook& pins, const BoardBus& bus, RigDevice& d) {
  const chips::ChipSpec& chip = *d.chip;
  if (bus.kind != BusKind::Serial)
    s.fail(s.line("bus"), "bus",
           fmt::format("chip {} is a servo on a serial bus, and {} is a{} bus", chip.name, d.bus,
                       bus.kind == BusKind::I2c ? "n I2C" : " SPI"));
  if (!chips::on_serial(chip))
    s.fail(s.line("chip"), "chip", fmt::format("{} is a serial (servo) bus, and chip {} is no servo", d.bus, chip.name));
  for (const char* k : {"cs", "clock_hz"})
    if (s.has(k)) s.fail(s.line(k), k, "not for a servo: a serial bus has no " + std::string(k) + " (give baud)");
  // Protocol 1.0 leaves 0xFE to broadcast; 2.0 also 0xFD (a header byte).
  const int top = chip.servo_protocol == 1 ? 253 : 252;
  if (!s.has("address"))
    s.fail(s.line(), "address", fmt::format("missing: the servo's id on the bus, 0..{}", top));
  d.address = int(s.integer("address", 0, top, fmt::format(" (a Dynamixel {}.0 id)", int(chip.servo_protocol))));
  pins.take(s, "address", fmt::format("{} id {}", d.bus, d.address));
  d.clock_hz = s.has("baud") ? uint32_t(s.integer("baud", 1, 100000000, " baud")) : chip.default_baud;
  const int baud_line = s.has("baud") ? s.line("baud") : s.line();
  if (d.clock_hz > chip.max_clock_hz)
    s.fail(baud_line, "baud", fmt::format("{} baud is above chip {}'s fastest, {}", d.clock_hz, chip.name,
                                          chip.max_clock_hz));
  if (!bus.makes_baud || !bus.makes_baud(d.clock_hz))
    s.fail(baud_line, "baud",
           fmt::format("bus {} cannot make {} baud within 2 % on board {} (at most {}; its divider is its clock / "
                       "baud, at least 16)",
                       d.bus, d.clock_hz, pins.board_name, bus.max_clock_hz));
  for (const RigDevice& o : rig.devices)
    if (o.bus == d.bus && o.clock_hz != d.clock_hz)
      s.fail(baud_line, "baud",
             fmt::format("{} baud, and device {} (line {}) runs bus {} at {}: one bus, one baud", d.clock_hz, o.name,
                         o.line, d.bus, o.clock_hz));
  d.release_on_fault = s.text("on_fault", "hold") == "release";
  if (s.has("on_fault")) (void)s.choice("on_fault", {"hold", "release"});
}

void read_devices(const std::string& file, const Section& root, const toml::table& t, Rig& rig, NameBook& names,
                  PinBook& pins) {
  const auto tables = table_array(root, t, "device");
  std::vector<std::string> chip_names, bus_names;
  for (const chips::ChipSpec* c : chips::kCatalog) chip_names.push_back(c->name);
  for (const BoardBus& b : pins.board->buses) bus_names.push_back(b.name);
  for (size_t i = 0; i < tables.size(); ++i) {
    const Section s(file, *tables[i], nth("device", i), line_of(*tables[i]),
                    {"name", "chip", "bus", "address", "cs", "clock_hz", "range", "rate_hz", "baud", "on_fault"});
    if (i >= size_t(RigCapacity::devices))
      s.fail(s.line(), "", "over capacity: at most " + std::to_string(RigCapacity::devices) + " devices");
    RigDevice d;
    d.line = s.line();
    d.name = s.text("name");
    names.add(s, d.name);
    d.chip = chips::find_chip(s.choice("chip", chip_names).c_str());
    const chips::ChipSpec& chip = *d.chip;
    d.bus = s.text("bus");
    d.bus_index = index_of(bus_names, d.bus);
    if (d.bus_index < 0)
      s.fail(s.line("bus"), "bus",
             "unknown bus '" + printable_excerpt(d.bus, 40) + "' on board " + pins.board_name + " (buses: " +
                 join(bus_names) + ")");
    const BoardBus& bus = pins.board->buses[size_t(d.bus_index)];
    d.kind = bus.kind;
    const bool serial_chip = chips::on_serial(chip);
    if (bus.kind == BusKind::Serial || serial_chip) {
      read_servo_device(s, rig, pins, bus, d);
    } else {
      read_chip_address(s, pins, bus, d);
    }
    // The bus's pins are its own from its first chip on: an ADC input on one is refused.
    const bool first_on_bus = std::none_of(rig.devices.begin(), rig.devices.end(),
                                           [&](const RigDevice& o) { return o.bus == d.bus; });
    if (first_on_bus)
      for (const std::string& pin : bus.pins) pins.take(s, "bus", pin);
    if (d.kind != BusKind::Serial) read_chip_clock(s, pins, bus, d);
    read_setting(s, "range", chip, chip.ranges, chip.range_count, chip.range_unit ? chip.range_unit : "", d.range,
                 d.range_bits);
    read_setting(s, "rate_hz", chip, chip.rates, chip.rate_count, "Hz", d.rate_hz, d.rate_bits);
    rig.devices.push_back(d);
  }
}


// source = "device": a channel of a [[device]], by the device's name and the
// chip's channel name.
void read_device_channel(const Section& s, const Rig& rig, RigSensor& sen) {
  const std::string device = s.text("device");
  std::vector<std::string> known;
  for (const RigDevice& d : rig.devices) known.push_back(d.name);
  sen.device = index_of(known, device);
  if (sen.device < 0)
    s.fail(s.line("device"), "device",
           "no [[device]] is named '" + printable_excerpt(device, 40) + "'" +
               (known.empty() ? std::string(" (the file has none)") : " (devices: " + join(known) + ")"));
  const chips::ChipSpec& chip = *rig.devices[size_t(sen.device)].chip;
  const std::vector<std::string> channels(chip.channel_names, chip.channel_names + chip.channel_count);
  const std::string channel = s.text("channel");
  sen.channel = index_of(channels, channel);
  if (sen.channel < 0)
    s.fail(s.line("channel"), "channel",
           fmt::format("chip {} (device {}) has no channel '{}' (channels: {})", chip.name, device,
                       printable_excerpt(channel, 40), join(channels)));
  read_scaling(s, sen.gain, sen.offset);
}


bool drives_an_input(const Rig& rig, int device) {
  return std::any_of(rig.inputs.begin(), rig.inputs.end(), [&](const RigInput& in) { return in.servo_device == device; });
}

// Each input's servo, by name: a [[device]] on a serial bus, one input per
// servo, whose goal stays inside the servo's goal range over [min, max].
void link_servos(const std::string& file, const Section& root, const toml::table& t, Rig& rig) {
  const auto tables = table_array(root, t, "input");
  for (size_t i = 0; i < rig.inputs.size(); ++i) {
    RigInput& in = rig.inputs[i];
    if (in.servo.empty()) continue;
    const Section s(file, *tables[i], nth("input", i), in.line,
                    {"name", "unit", "min", "max", "neutral", "pwm", "servo", "goal_per_unit", "goal_at_neutral"});
    std::vector<std::string> servos;
    for (size_t d = 0; d < rig.devices.size(); ++d) {
      if (!chips::on_serial(*rig.devices[d].chip)) continue;
      servos.push_back(rig.devices[d].name);
      if (rig.devices[d].name == in.servo) in.servo_device = int(d);
    }
    if (in.servo_device < 0)
      s.fail(in.servo_line, "servo",
             "no servo [[device]] is named '" + printable_excerpt(in.servo, 40) + "'" +
                 (servos.empty() ? std::string(" (the file has none: a device with a servo chip on a serial bus)")
                                 : " (servos: " + join(servos) + ")"));
    for (size_t j = 0; j < i; ++j)
      if (rig.inputs[j].servo_device == in.servo_device)
        s.fail(in.servo_line, "servo",
               fmt::format("servo {} already drives input {} (line {}): one servo, one input", in.servo,
                           rig.inputs[j].name, rig.inputs[j].servo_line));
    const chips::ChipSpec& chip = *rig.devices[size_t(in.servo_device)].chip;
    for (const auto& [key, u] : {std::pair<const char*, double>{"min", in.min}, {"max", in.max}}) {
      const double goal = in.goal_at_neutral + in.goal_per_unit * (u - in.neutral);
      if (!(goal >= 0.0 && goal <= double(chip.goal_max)))
        s.fail(s.line("goal_per_unit"), "goal_per_unit",
               fmt::format("puts {} = {} at goal {} (goal_at_neutral + goal_per_unit * ({} - neutral)), outside "
                           "chip {}'s goal range 0..{}",
                           key, num(u), num(goal), key, chip.name, chip.goal_max));
    }
  }
}

void read_sensors(const std::string& file, const Section& root, const toml::table& t, Rig& rig, NameBook& names,
                  PinBook& pins) {
  const auto tables = table_array(root, t, "sensor");
  std::vector<int> read_by(rig.devices.size(), 0);
  for (size_t i = 0; i < tables.size(); ++i) {
    const Section s(file, *tables[i], nth("sensor", i), line_of(*tables[i]),
                    {"name", "unit", "source", "adc", "device", "channel", "gain", "offset"});
    if (i >= size_t(RigCapacity::w))
      s.fail(s.line(), "", "over capacity: at most w = " + std::to_string(RigCapacity::w) + " sensors");
    RigSensor sen;
    sen.name = s.text("name");
    names.add(s, sen.name);
    sen.unit = s.line_text("unit", "");
    const std::string source = s.choice("source", {"adc", "device", "none"});
    sen.line = s.line();
    if (source == "adc") {
      refuse_keys(s, source, {"device", "channel"}, "source = \"device\"");
      sen.source = SensorSource::Adc;
      sen.adc_line = s.line("adc");
      read_adc(s, pins, sen.adc, sen.gain, sen.offset);
    } else if (source == "device") {
      refuse_keys(s, source, {"adc"}, "source = \"adc\"");
      sen.source = SensorSource::Device;
      read_device_channel(s, rig, sen);
      ++read_by[size_t(sen.device)];
    } else {
      refuse_keys(s, source, {"adc", "device", "channel", "gain", "offset"}, "source = \"adc\" or \"device\"");
    }
    rig.sensors.push_back(sen);
  }
  // A chip nobody reads would still be configured and polled, its faults
  // reported: a device left over from an edit, refused rather than kept.
  for (size_t d = 0; d < rig.devices.size(); ++d)
    if (read_by[d] == 0 && !drives_an_input(rig, int(d))) {
      const Section s(file, *table_array(root, t, "device")[d], nth("device", d), rig.devices[d].line,
                      {"name", "chip", "bus", "address", "cs", "clock_hz", "range", "rate_hz", "baud", "on_fault"});
      s.fail(s.line("name"), "name",
             "no [[sensor]] reads device '" + rig.devices[d].name +
                 "': give a sensor source = \"device\" with device = \"" + rig.devices[d].name + "\"" +
                 (chips::on_serial(*rig.devices[d].chip) ? ", or an [[input]] servo = \"" + rig.devices[d].name + "\""
                                                        : std::string()) +
                 ", or remove the device");
    }
}

// The controller's defaults go through the very checks a PARAM_SET does
// (shared/params.hpp set_param), in an order where each write is valid on
// its own (horizons before the control horizon), so the file and the wire
// refuse the same values.
void read_controller(const std::string& file, const Section& root, const toml::table& t, Rig& rig,
                     const LimitLines& limit_lines) {
  const toml::table* ct = sub_table(root, t, "controller");
  if (!ct) root.fail(root.line(), "[controller]", "missing table (the controller's defaults: Q, Lambda, s, b, r, N, Nc, eps)");
  const Section s(file, *ct, "[controller]", line_of(*ct),
                  {"Q", "Lambda", "s", "b", "r", "N", "N1", "Nc", "eps", "nr_tol", "nr_max_iter", "mode", "feedback"});
  const int m = rig.m(), n = rig.n();
  Params<RigCapacity> P;
  // u_min/u_max come from the [[input]] tables (already min < max).
  for (int i = 0; i < m; ++i) P.u_max[i] = kParamTable[uint8_t(ParamId::UMax)].max;
  auto set = [&](ParamId id, const std::vector<double>& v, const std::string& key, const Section& at,
                 const std::string& count_why) {
    const ParamDesc& d = kParamTable[uint8_t(id)];
    std::vector<float> f(v.begin(), v.end());
    const ParamResult r = set_param(P, id, f.data(), int(f.size()), m, n);
    if (r.status == Status::Ok) return;
    const bool per = d.size != ParamSize::Scalar;
    const std::string k = per && r.index >= 0 ? key + "[" + std::to_string(r.index) + "]" : key;
    const int line = per ? at.element_line(key, r.index) : at.line(key);
    const double x = r.index >= 0 && size_t(r.index) < v.size() ? v[size_t(r.index)] : (v.empty() ? 0 : v[0]);
    switch (r.status) {
      case Status::WrongSize:
        at.fail(at.line(key), key,
                "expects " + std::to_string(param_count(d, m, n)) + " values " + count_why + ", got " +
                    std::to_string(v.size()));
      case Status::NotFinite: at.fail(line, k, "must be finite, not " + num(x));
      case Status::OutOfRange:
        at.fail(line, k,
                "out of range: " + num(x) + " is not in [" + num(d.min) + ", " + num(d.max) + "]" +
                    (d.type == ParamType::F32 ? "" : ", a whole number") + " (the range PARAM_SET accepts)");
      case Status::TooLarge:
        at.fail(line, k,
                "over capacity: " + num(x) + " exceeds the controller's " +
                    (id == ParamId::N ? "N <= " + std::to_string(RigCapacity::N)
                                      : "Nc <= " + std::to_string(RigCapacity::Nc)));
      case Status::Inconsistent:
        if (id == ParamId::Nc || id == ParamId::N1)
          at.fail(line, k, "must be <= N (" + std::to_string(int(P.N)) + " at line " + std::to_string(s.line("N")) + ")");
        if (id == ParamId::N)
          at.fail(line, k, "must be >= Nc and N1 (" + std::to_string(int(P.Nc)) + ", " + std::to_string(int(P.N1)) + ")");
        at.fail(line, k, "must keep every input's min < max");
      default: at.fail(line, k, std::string("refused (") + status_name(r.status) + ")");
    }
  };

  // The input limits, element by element from their own tables.
  {
    std::vector<double> lo, hi;
    for (const RigInput& in : rig.inputs) lo.push_back(in.min), hi.push_back(in.max);
    const ParamResult a = set_param(P, ParamId::UMin, std::vector<float>(lo.begin(), lo.end()).data(), m, m, n);
    const ParamResult b = a.status == Status::Ok
                              ? set_param(P, ParamId::UMax, std::vector<float>(hi.begin(), hi.end()).data(), m, m, n)
                              : a;
    if (b.status != Status::Ok) {
      const ParamDesc& d = kParamTable[uint8_t(ParamId::UMin)];
      const int i = b.index < 0 ? 0 : b.index;
      const std::string key = a.status != Status::Ok ? "min" : "max";
      const double x = key == "min" ? lo[size_t(i)] : hi[size_t(i)];
      const int line = limit_lines[size_t(i)][key == "min" ? 0 : 1];
      throw RigError(file + ":" + std::to_string(line) + ": [[input]] #" + std::to_string(i + 1) + " " + key +
                         ": out of range: " + num(x) + " is not in [" + num(d.min) + ", " + num(d.max) +
                         "] (the range PARAM_SET accepts)",
                     file, line, key);
    }
  }

  const std::string per_out = "(one per [[output]])", per_in = "(one per [[input]])";
  RigController& c = rig.controller;
  c.Q = s.numbers("Q", false);
  set(ParamId::Q, c.Q, "Q", s, per_out);
  c.Lambda = s.numbers("Lambda", false);
  set(ParamId::Lambda, c.Lambda, "Lambda", s, per_in);
  c.s = s.raw_number("s");
  set(ParamId::S, {c.s}, "s", s, "");
  c.b = s.raw_number("b");
  set(ParamId::B, {c.b}, "b", s, "");
  c.r = s.raw_number("r");
  set(ParamId::R, {c.r}, "r", s, "");
  c.N = int(s.integer("N", 1, 255));
  set(ParamId::N, {double(c.N)}, "N", s, "");
  if (s.has("N1")) c.N1 = int(s.integer("N1", 1, 255));
  set(ParamId::N1, {double(c.N1)}, "N1", s, "");
  c.Nc = int(s.integer("Nc", 1, 255));
  set(ParamId::Nc, {double(c.Nc)}, "Nc", s, "");
  c.eps = s.raw_number("eps");
  set(ParamId::Eps, {c.eps}, "eps", s, "");
  if (s.has("nr_tol")) c.nr_tol = s.raw_number("nr_tol");
  set(ParamId::NrTol, {c.nr_tol}, "nr_tol", s, "");
  if (s.has("nr_max_iter")) c.nr_max_iter = int(s.integer("nr_max_iter", 0, 255));
  set(ParamId::NrMaxIter, {double(c.nr_max_iter)}, "nr_max_iter", s, "");
  if (s.has("mode")) c.mode = s.choice("mode", {"exact", "fd"}) == "fd" ? DerivMode::Fd : DerivMode::Exact;
  set(ParamId::Mode, {double(uint8_t(c.mode))}, "mode", s, "");
  if (s.has("feedback"))
    c.feedback = s.choice("feedback", {"predicted", "measured"}) == "measured" ? Feedback::Measured : Feedback::Predicted;
  set(ParamId::Feedback, {double(uint8_t(c.feedback))}, "feedback", s, "");
}

void read_model(const std::string& file, const Section& root, const toml::table& t, Rig& rig) {
  const toml::table* mt = sub_table(root, t, "model");
  if (!mt) return;
  const Section s(file, *mt, "[model]", line_of(*mt), {"file", "layer"});
  rig.model.file = s.line_text("file", "");
  // A file among the models (NLSOFT_MODELS, the shipped ones), never a path
  // out of that folder; another file is given on the command line (--model).
  if (s.has("file") && (rig.model.file.empty() || rig.model.file.find('/') != std::string::npos ||
                        rig.model.file == "." || rig.model.file == ".."))
    s.fail(s.line("file"), "file",
           "'" + rig.model.file +
               "' is not a file name among the models (no '/'): give another model with --model FILE");
  const auto layers = table_array(s, *mt, "layer");
  for (size_t i = 0; i < layers.size(); ++i) {
    const Section l(file, *layers[i], nth("model.layer", i), line_of(*layers[i]), {"kind", "units", "activation"});
    if (i >= size_t(HostCapacity::layers))
      l.fail(l.line(), "", "over capacity: at most " + std::to_string(HostCapacity::layers) + " layers");
    RigLayer L;
    std::vector<std::pair<std::string, LayerKind>> kinds;
    for (const LayerKindInfo& k : kLayerKinds) kinds.push_back({k.name, k.kind});
    L.kind = l.choice("kind", kinds);
    // A layer's columns (a GRU's gates: 3 x units) within the widest the console holds.
    const LayerKindInfo& kind = layer_kind_info(L.kind);
    L.units = int(l.integer("units", 1, HostCapacity::width / kind.gates,
                            kind.gates > 1 ? fmt::format(" (a {} is {} x units wide, at most {})", kind.title, kind.gates,
                                                         HostCapacity::width)
                                           : ""));
    if (kind.free_activation) {
      std::vector<std::string> acts;
      for (uint8_t a = 0; activation_valid(a); ++a) acts.push_back(activation_name(Activation(a)));
      L.activation = l.has("activation") ? l.choice("activation", acts) : activation_name(kind.act);
    } else if (l.has("activation")) {
      l.fail(l.line("activation"), "activation",
             fmt::format("not for kind = \"{}\" (a {}'s activations are fixed)", kind.name, kind.title));
    }
    rig.model.layers.push_back(L);
  }
  if (!layers.empty() && rig.model.layers.back().units != rig.n()) {
    const Section last(file, *layers.back(), nth("model.layer", layers.size() - 1), line_of(*layers.back()),
                       {"kind", "units", "activation"});
    last.fail(last.line("units"), "units",
              "the last layer predicts the outputs: must be n = " + std::to_string(rig.n()) + " (the [[output]] tables), not " +
                  std::to_string(rig.model.layers.back().units));
  }
}

// A generic plant's constants (docs/rig-file.md, shared/plant_generic.hpp):
// each checked where it is written, so the plant never refuses what the
// file holds.
void read_generic_plant(const std::string& file, const Section& s, const toml::table& pt, Rig& rig) {
  constexpr double kBig = 1e6, kTauMax = 1e3;
  RigPlant& p = rig.plant;
  const int m = rig.m(), n = rig.n(), w = rig.w();
  const auto tables = table_array(s, pt, "actuator");
  const Section::Count per_in{"m", m, "one per [[input]]"}, per_out{"n", n, "one per [[output]]"};
  const Section::Count per_sensor{"w", w, "one per [[sensor]]"};
  const Section::Count per_state{"m + n", m + n, "one per [[input]], then one per [[output]]"};
  if (tables.size() < size_t(m))
    s.fail(s.line(), "[[plant.actuator]]", "expected " + per_in.text("tables") + ", got " + std::to_string(tables.size()));
  for (size_t i = 0; i < tables.size(); ++i) {
    const Section a(file, *tables[i], nth("plant.actuator", i), line_of(*tables[i]),
                    {"gain", "shape", "knee", "exponent", "play", "tau"});
    if (i >= size_t(m)) a.fail(a.line(), "", "one more than the " + std::to_string(m) + " [[input]] tables");
    const RigInput& in = rig.inputs[i];
    RigActuator act;
    act.gain = a.has("gain") ? a.bounded("gain", -kBig, kBig) : 1.0;
    if (act.gain == 0) a.fail(a.line("gain"), "gain", "must not be 0 (the actuator would move nothing)");
    if (a.has("shape")) {
      std::vector<std::pair<std::string, GenericShape>> shapes;
      for (const GenericShapeName& g : kGenericShapes) shapes.emplace_back(g.name, g.shape);
      act.shape = a.choice("shape", shapes);
    }
    const bool kneed = act.shape == GenericShape::Tanh || act.shape == GenericShape::Saturation;
    if (kneed) {
      act.knee = a.bounded("knee", 0, kBig);
      if (!(act.knee > 0)) a.fail(a.line("knee"), "knee", "must be > 0, not " + num(act.knee));
    } else if (a.has("knee")) {
      a.fail(a.line("knee"), "knee", "only for shape = \"tanh\" or \"saturation\"");
    }
    if (act.shape == GenericShape::Power) {
      act.exponent = a.bounded("exponent", 0, 8);
      if (!(act.exponent > 0)) a.fail(a.line("exponent"), "exponent", "must be > 0, not " + num(act.exponent));
    } else if (a.has("exponent")) {
      a.fail(a.line("exponent"), "exponent", "only for shape = \"power\"");
    }
    const double half = 0.5 * (in.max - in.min);
    if (a.has("play")) {
      act.play = a.bounded("play", 0, kBig);
      if (!(act.play < half))
        a.fail(a.line("play"), "play",
               "must be < half the input's range, " + num(half) + ": a wider play never moves the actuator");
    }
    if (a.has("tau")) act.tau = a.bounded("tau", 0, kTauMax, " s (a time constant)");
    p.actuators.push_back(act);
  }
  p.coupling = s.matrix("coupling", per_out, per_in, kBig);
  p.output_offset.clear();
  if (s.has("output_offset")) {
    p.output_offset = s.vector("output_offset", per_out, -kBig, kBig);
  } else {
    for (const RigOutput& o : rig.outputs) p.output_offset.push_back(0.5 * (o.min + o.max));
  }
  p.output_tau = s.has("output_tau") ? s.vector("output_tau", per_out, 0, kTauMax) : std::vector<double>(size_t(n), 0.0);
  if (w > 0) {
    p.sensor_map = s.matrix("sensor_map", per_sensor, per_state, kBig);
  } else if (s.has("sensor_map")) {
    s.fail(s.line("sensor_map"), "sensor_map", "the file has no [[sensor]] tables");
  }
  p.sensor_offset = s.has("sensor_offset") ? s.vector("sensor_offset", per_sensor, -kBig, kBig)
                                           : std::vector<double>(size_t(w), 0.0);
  p.sensor_noise = s.has("sensor_noise") ? s.vector("sensor_noise", per_sensor, 0, kBig)
                                         : std::vector<double>(size_t(w), 0.0);
}

// The simulated stand-in: one of the plants the console carries, whose
// dimensions must be the file's, or a generic plant described key by key.
void read_plant(const std::string& file, const Section& root, const toml::table& t, Rig& rig) {
  const toml::table* pt = sub_table(root, t, "plant");
  if (!pt) return;
  const std::vector<std::string> generic_keys = {"coupling",      "output_offset", "output_tau", "sensor_map",
                                                 "sensor_offset", "sensor_noise",  "actuator"};
  std::vector<std::string> known = {"kind"};
  known.insert(known.end(), generic_keys.begin(), generic_keys.end());
  const Section s(file, *pt, "[plant]", line_of(*pt), known);
  std::vector<std::string> kinds;
  for (const PlantEntry& e : kPlantRegistry) kinds.push_back(e.name);
  const PlantEntry* plant = find_plant(s.choice("kind", kinds).c_str());
  rig.plant.kind = plant;
  rig.plant.line = s.line("kind");
  if (plant->kind == PlantKind::Generic) return read_generic_plant(file, s, *pt, rig);
  for (const std::string& k : generic_keys)
    if (s.has(k))
      s.fail(s.line(k), k,
             std::string("only for kind = \"generic\" (plant '") + plant->name + "' has its constants compiled in)");
  auto same = [&](const char* dim, int plant_dim, int file_dim, const char* tables) {
    if (plant_dim != file_dim)
      s.fail(s.line("kind"), "kind",
             std::string("plant '") + plant->name + "' has " + dim + " = " + std::to_string(plant_dim) +
                 ", but the file has " + std::to_string(file_dim) + " " + tables);
  };
  same("m", plant->m, rig.m(), "[[input]] tables");
  same("n", plant->n, rig.n(), "[[output]] tables");
  same("w", plant->w, rig.w(), "[[sensor]] tables");
  // The plant steps at the rig's period (the simulator's and the HIL
  // image's loop), whatever rate the hand-written plant was tuned at.
}

void read_reference(const std::string& file, const Section& root, const toml::table& t, Rig& rig) {
  RigReference& r = rig.reference;
  // Without a [reference] table: an Infinity path around the middle of the
  // outputs' ranges, a quarter of each span wide.
  for (int i = 0; i < 3 && i < rig.n(); ++i) {
    r.centre[size_t(i)] = 0.5 * (rig.outputs[size_t(i)].min + rig.outputs[size_t(i)].max);
    r.amplitude[size_t(i)] = 0.25 * rig.outputs[size_t(i)].span;
  }
  const double span0 = rig.outputs[0].span;
  r.step_levels = {span0 / 4, span0 / 2, span0};
  const toml::table* rt = sub_table(root, t, "reference");
  if (rt) {
    const Section s(file, *rt, "[reference]", line_of(*rt),
                    {"kind", "centre", "amplitude", "pringle_amplitude", "swirl_centre", "swirl_scale", "step_levels"});
    if (s.has("kind")) {
      const std::string k = s.choice("kind", {"infinity", "pringle", "diagonal", "swirl", "steps"});
      r.kind = k == "infinity" ? RefKind::Infinity
               : k == "pringle" ? RefKind::Pringle
               : k == "diagonal" ? RefKind::Diagonal
               : k == "swirl"    ? RefKind::Swirl
                                 : RefKind::Step;
    }
    if (s.has("centre")) r.centre = s.triple("centre");
    if (s.has("amplitude")) r.amplitude = s.triple("amplitude");
    r.pringle_amplitude = s.has("pringle_amplitude") ? s.triple("pringle_amplitude") : r.amplitude;
    r.swirl_centre = s.has("swirl_centre") ? s.triple("swirl_centre") : r.centre;
    if (s.has("swirl_scale")) r.swirl_scale = s.positive("swirl_scale");
    if (s.has("step_levels")) {
      r.step_levels = s.numbers("step_levels");
      if (r.step_levels.empty() || r.step_levels.size() > size_t(kRefMaxLevels))
        s.fail(s.line("step_levels"), "step_levels",
               "expected 1 to " + std::to_string(kRefMaxLevels) + " levels, got " + std::to_string(r.step_levels.size()));
    }
    return;
  }
  r.pringle_amplitude = r.amplitude;
  r.swirl_centre = r.centre;
}

// One [ident] or [ident.SIGNAL] table: amplitude and band, by the rules
// IDENT_START's are checked by (shared/excitation.hpp), so a file never
// holds what the firmware would refuse.
void read_ident_choice(const Section& s, double rate_hz, RigIdentChoice& c) {
  ExcitationSpec spec;
  spec.band_lo = spec.band_hi = float(rate_hz / 4);  // a band any rate samples, where the table sets none
  if (s.has("amplitude")) {
    c.amplitude = s.number("amplitude");
    c.amplitude_from = s.where();
    spec.amplitude = float(c.amplitude);
  }
  if (s.has("band")) {
    const std::vector<double> b = s.numbers("band");
    if (b.size() != 2) s.fail(s.line("band"), "band", "expected [LO, HI] in Hz, 2 numbers, got " + std::to_string(b.size()));
    c.band_lo = b[0], c.band_hi = b[1], c.band_from = s.where();
    spec.band_lo = float(b[0]), spec.band_hi = float(b[1]);
  }
  const ExcitationCheck k = check_excitation(spec, float(rate_hz));
  switch (k.field) {
    case ExcitationField::Amplitude:
      s.fail(s.line("amplitude"), "amplitude",
             "must be in (0, 1], the fraction of each input's range the signal spans, not " + num(c.amplitude));
    case ExcitationField::BandLo:
      s.fail(s.line("band"), "band", "its lower edge must be > 0 Hz, not " + num(c.band_lo));
    case ExcitationField::BandHi:
      if (k.status == Status::Inconsistent)
        s.fail(s.line("band"), "band", "its lower edge " + num(c.band_lo) + " Hz is above its upper " + num(c.band_hi));
      s.fail(s.line("band"), "band",
             "reaches past half the loop rate (" + num(rate_hz / 2) + " Hz at rate_hz = " + num(rate_hz) +
                 "): nothing above it can be sampled, not " + num(c.band_hi) + " Hz");
    default:
      break;
  }
}

void read_ident(const std::string& file, const Section& root, const toml::table& t, Rig& rig) {
  const toml::table* it = sub_table(root, t, "ident");
  if (!it) return;
  std::vector<std::string> known = {"amplitude", "band"};
  known.insert(known.end(), std::begin(kExcitationSignalNames), std::end(kExcitationSignalNames));
  const Section s(file, *it, "[ident]", line_of(*it), known);
  read_ident_choice(s, rig.rate_hz, rig.ident.all);
  for (uint8_t i = 0; i < kExcitationSignalCount; ++i) {
    const std::string name = kExcitationSignalNames[i], where = "[ident." + name + "]";
    const toml::node* n = it->get(name);
    if (!n) continue;
    if (!n->is_table()) s.fail(line_of(*n), name, "expected a table " + where + ", got " + type_name(*n));
    const Section own(file, *n->as_table(), where, line_of(*n), {"amplitude", "band"});
    read_ident_choice(own, rig.rate_hz, rig.ident.signal[i]);
  }
}

// [pid]: gains >= 0, a non-zero output scale, a filter time >= 0 (what
// Pid::configure takes), on a rig whose inputs and outputs pair up.
void read_pid(const std::string& file, const Section& root, const toml::table& t, Rig& rig) {
  const toml::table* pt = sub_table(root, t, "pid");
  if (!pt) return;
  const Section s(file, *pt, "[pid]", line_of(*pt), {"kp", "ki", "kd", "output_scale", "d_filter_tau"});
  if (rig.m() != rig.n() || rig.n() > kPidMaxAxes)
    s.fail(s.line(), "",
           fmt::format("the PID baseline runs one loop per axis, output i on input i: it needs as many inputs as "
                       "outputs, at most {} (this rig: m = {}, n = {})",
                       kPidMaxAxes, rig.m(), rig.n()));
  auto nonnegative = [&](const char* key, double fallback) {
    const double v = s.number(key, fallback);
    if (v < 0) s.fail(s.line(key), key, "must be >= 0, not " + num(v));
    return v;
  };
  rig.pid.given = true;
  rig.pid.line = s.line();
  rig.pid.kp = nonnegative("kp", 0);
  rig.pid.ki = nonnegative("ki", 0);
  rig.pid.kd = nonnegative("kd", 0);
  rig.pid.output_scale = s.number("output_scale", 1);
  if (rig.pid.output_scale == 0) s.fail(s.line("output_scale"), "output_scale", "must not be 0");
  rig.pid.d_filter_tau = nonnegative("d_filter_tau", 0);
  if (rig.pid.kp == 0 && rig.pid.ki == 0 && rig.pid.kd == 0)
    s.fail(s.line(), "", "give kp, ki or kd > 0 (with every gain 0 the input never moves)");
}

// [firmware] features = ["ident", ...]: each a name of shared/firmware_features.hpp,
// once, and one the rig's board can carry.
void read_firmware(const std::string& file, const Section& root, const toml::table& t, Rig& rig,
                   const BoardPins* board) {
  const toml::table* ft = sub_table(root, t, "firmware");
  if (!ft) return;
  const Section s(file, *ft, "[firmware]", line_of(*ft), {"features", "optimize"});
  if (s.has("optimize")) rig.firmware_size_first = s.choice("optimize", {"speed", "size"}) == "size";
  if (!s.has("features")) return;
  std::vector<std::string> known;
  for (const FirmwareFeature& f : kFirmwareFeatures) known.push_back(std::string("\"") + f.name + "\"");
  const toml::node& n = s.node("features");
  if (!n.is_array())
    s.fail(line_of(n), "features",
           std::string("expected a list of services, e.g. [\"ident\", \"settings\"] (or [] for the minimum), got ") +
               type_name(n));
  uint32_t features = 0;
  const toml::array& a = *n.as_array();
  for (size_t i = 0; i < a.size(); ++i) {
    const std::string at = "features[" + std::to_string(i) + "]";
    if (!a[i].is_string()) s.fail(line_of(a[i]), at, std::string("expected a service's name, got ") + type_name(a[i]));
    const std::string name = a[i].as_string()->get();
    const FirmwareFeature* found = nullptr;
    for (const FirmwareFeature& f : kFirmwareFeatures)
      if (name == f.name) found = &f;
    if (!found)
      s.fail(line_of(a[i]), at,
             "'" + printable_excerpt(name, 40) + "' is not a service an image can leave out (known: " + join(known) +
                 "; the link, parameters, runs on the compiled-in references and telemetry are always there)");
    if (features & found->bit) s.fail(line_of(a[i]), at, "'" + name + "' is listed twice");
    if (board) {
      if (const std::string why = board_lacks(*board, *found); !why.empty())
        s.fail(line_of(a[i]), at, "'" + name + "': " + why + "; leave it out");
    }
    features |= found->bit;
  }
  rig.firmware_features = features;
  rig.firmware_line = s.line("features");
}

}  // namespace

const char* output_source_name(OutputSource s) {
  return s == OutputSource::Adc ? "adc" : (s == OutputSource::External ? "external" : "none");
}
const char* sensor_source_name(SensorSource s) {
  return s == SensorSource::Adc ? "adc" : (s == SensorSource::Device ? "device" : "none");
}

Rig parse_rig(const std::string& text, const std::string& file) {
  toml::table t;
  try {
    t = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    const int line = int(e.source().begin.line);
    throw RigError(file + ":" + std::to_string(line) + ": " + std::string(e.description()), file, line, "");
  }
  const Section root(file, t, "", 1,
                     {"name", "description", "info_platform", "rate_hz", "nd", "dd", "board", "input", "output", "sensor", "device", "controller",
                      "model", "plant", "reference", "ident", "pid", "firmware"});
  Rig rig;
  rig.file = file;
  rig.hash = rig_file_hash(text);
  rig.name = root.text("name");
  if (rig.name.empty() || rig.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_-") != std::string::npos)
    root.fail(root.line("name"), "name",
              "'" + printable_excerpt(rig.name, 40) + "' is not a command-line name (a-z, 0-9, '-', '_')");
  if (rig.name.size() > size_t(kRigMaxNameLen))
    root.fail(root.line("name"), "name",
              fmt::format("'{}' is {} characters; a rig's name travels in {} at most", rig.name, rig.name.size(),
                          kRigMaxNameLen));
  rig.description = root.line_text("description", "");
  if (root.has("info_platform"))
    rig.info_platform = uint8_t(root.integer("info_platform", 0, kPlatformCount - 1,
                                             " (the numbers protocol/PROTOCOL.md assigns to shipped rigs)"));
  // A period from 10 us (the firmware's loop) to 1000 s (a slow process:
  // the cascaded tanks are sampled every 4 s); a simulated plant steps at
  // most kMaxPlantDt, checked with [plant] below.
  rig.rate_hz = root.bounded("rate_hz", 1e-3, 1e5, " Hz");
  // The controller keeps one history length for u and y (paper: n_d = d_d).
  // Left out, or "auto" (both keys alike): `train` chooses it from the data
  // (app/model/lag_search.hpp); until a model says otherwise the rig holds
  // the longest its inputs leave room for, set below.
  auto auto_lags = [&](const char* key) {
    if (!root.has(key)) return true;
    if (!root.node(key).is_string()) return false;
    const std::string v = root.text(key);
    if (v != "auto")
      root.fail(root.line(key), key, "'" + printable_excerpt(v, 40) + "' is not a history length: an integer, or \"auto\"");
    return true;
  };
  const bool nd_auto = auto_lags("nd"), dd_auto = auto_lags("dd");
  if (nd_auto != dd_auto)
    root.fail(root.line(nd_auto ? "dd" : "nd"), nd_auto ? "dd" : "nd",
              std::string("is set while ") + (nd_auto ? "nd" : "dd") +
                  " is left to train's search: give both (equal) or neither");
  rig.lags_auto = nd_auto;
  rig.nd = rig.lags_auto ? 1 : int(root.integer("nd", 1, RigCapacity::nd));
  rig.dd = rig.lags_auto ? 1 : int(root.integer("dd", 1, RigCapacity::nd));
  if (rig.dd != rig.nd)
    root.fail(root.line("dd"), "dd",
              "must equal nd (" + std::to_string(rig.nd) + " at line " + std::to_string(root.line("nd")) +
                  "): the controller keeps one history length");

  PinBook pins;
  pins.board_name = root.has("board") ? root.choice("board", board_names()) : "stm32f4";
  pins.board = find_board(pins.board_name);
  rig.board = pins.board_name;
  NameBook names;
  LimitLines limit_lines;
  read_inputs(file, root, t, rig, names, pins, limit_lines);
  read_outputs(file, root, t, rig, names, pins);
  read_devices(file, root, t, rig, names, pins);
  link_servos(file, root, t, rig);
  read_sensors(file, root, t, rig, names, pins);
  if (rig.lags_auto)
    rig.nd = rig.dd = std::max(1, std::min(RigCapacity::nd, (RigCapacity::p - rig.w()) / (rig.m() + rig.n())));
  if (const int p = rig.nd * rig.m() + rig.dd * rig.n() + rig.w(); p > RigCapacity::p)
    root.fail(root.line("nd"), "nd",
              fmt::format("the network's input p = nd m + dd n + w = {}*{} + {}*{} + {} = {} exceeds {}: shorten the "
                          "histories to nd = dd <= {}",
                          rig.nd, rig.m(), rig.dd, rig.n(), rig.w(), p, RigCapacity::p,
                          (RigCapacity::p - rig.w()) / (rig.m() + rig.n())));
  read_controller(file, root, t, rig, limit_lines);
  read_model(file, root, t, rig);
  read_plant(file, root, t, rig);
  if (rig.plant.kind != nullptr && rig.rate_hz < 1.0 / double(kMaxPlantDt))
    root.fail(root.line("rate_hz"), "rate_hz",
              "must be at least " + num(1.0 / double(kMaxPlantDt)) + " Hz with a [plant] (line " +
                  std::to_string(rig.plant.line) + "): a simulated plant steps at most " + num(double(kMaxPlantDt)) +
                  " s, not " + num(rig.rate_hz));
  read_reference(file, root, t, rig);
  read_ident(file, root, t, rig);
  read_pid(file, root, t, rig);
  read_firmware(file, root, t, rig, pins.board);
  return rig;
}

uint32_t rig_file_hash(const std::string& text) {
  // Hand-written: the canonical form is this protocol's definition
  // (PROTOCOL.md 7, RIG_INFO), not a TOML writer's, so that an image build
  // and any console compute it the same way without a TOML library.
  Crc32 crc;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::string kept;
    kept.reserve(line.size());
    for (char c : line)
      if (c != '\r') kept += c;
    while (!kept.empty() && (kept.back() == ' ' || kept.back() == '\t')) kept.pop_back();
    const size_t first = kept.find_first_not_of(" \t");
    if (first == std::string::npos || kept[first] == '#') continue;
    kept += '\n';
    crc.update(reinterpret_cast<const uint8_t*>(kept.data()), kept.size());
  }
  return crc.value();
}

namespace {
std::atomic<long> g_loaded{0};
}  // namespace

long rig_files_loaded() { return g_loaded.load(); }

Rig load_rig(const std::string& path) {
  ++g_loaded;
  std::string text;
  try {
    text = read_input_file(path, kRigFile);
  } catch (const CliError& e) {
    throw RigError(e.what(), path, 0, "");
  }
  return parse_rig(text, path);
}

}  // namespace nlsoft::host
