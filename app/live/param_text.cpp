#include "app/live/param_text.hpp"

#include <fmt/format.h>
#include <strings.h>

#include <cstdlib>

#include "host/files/cli_error.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

struct Entry {
  const char* name;
  const char* description;
  std::vector<ParamOption> options;
};

// Written for someone tuning on the rig: what turning the knob does.
const std::vector<Entry>& entries() {
  static const std::vector<Entry> e = {
      {"Q", "tracking weight per output (diagonal of Q): larger follows the reference harder", {}},
      {"Lambda", "weight on input changes per actuator (diagonal of Lambda): larger gives smoother, slower u", {}},
      {"s", "barrier scale: how hard the soft wall at b +- r/2 pushes inputs back; tiny keeps it soft", {}},
      {"b", "barrier centre, in input units", {}},
      {"r", "barrier range: the wall sits at b +- r/2 around each input", {}},
      {"N", "prediction horizon: control steps the model predicts ahead", {}},
      {"N1", "first predicted step counted in the cost (the last is N)", {}},
      {"Nc", "control horizon (<= N): inputs beyond it repeat the last", {}},
      {"eps", "finite-difference step for the derivatives (mode fd only)", {}},
      {"u_min", "lower input limit per actuator: u is never below it", {}},
      {"u_max", "upper input limit per actuator: u is never above it", {}},
      {"nr_tol", "Newton-Raphson stops when the largest input change falls below this", {}},
      {"nr_max_iter", "Newton-Raphson iteration cap per control step", {}},
      {"mode", "derivatives of the cost: exact (chain rule through the network) or fd (central differences)",
       {{"exact", 0}, {"fd", 1}}},
      {"feedback", "y history fed to the model: predicted (its own predictions) or measured (the plant's output)",
       {{"predicted", 0}, {"measured", 1}}},
      {"watchdog_ms", "link silence during a run before the firmware goes to safe_state; 0 turns it off", {}},
      {"safe_state", "what the firmware does when the watchdog trips: hold (keep the last u) or neutral",
       {{"hold", 0}, {"neutral", 1}}},
  };
  return e;
}

const Entry* find(const std::string& name) {
  for (const Entry& e : entries())
    if (name == e.name) return &e;
  for (const Entry& e : entries())
    if (strcasecmp(name.c_str(), e.name) == 0) return &e;
  return nullptr;
}

bool is_number(const std::string& t) {
  char* end = nullptr;
  std::strtod(t.c_str(), &end);
  return end != t.c_str() && *end == '\0';
}

}  // namespace

std::string param_description(const std::string& name) {
  const Entry* e = find(name);
  return e ? e->description : "";
}

const std::vector<ParamOption>& param_options(const std::string& name) {
  static const std::vector<ParamOption> none;
  const Entry* e = find(name);
  return e ? e->options : none;
}

std::string param_options_text(const std::string& name) {
  std::string s;
  for (const ParamOption& o : param_options(name)) s += fmt::format("{}{} ({:g})", s.empty() ? "" : ", ", o.name, o.value);
  return s;
}

std::vector<std::string> expand_param_tokens(const ParamInfo& p, const std::vector<std::string>& tokens) {
  const auto& options = param_options(p.name);
  std::vector<std::string> out;
  for (const std::string& raw : tokens) {
    // Commas separate values as blanks do (the catalog's parser reads both).
    size_t pos = 0;
    while (pos <= raw.size()) {
      const size_t comma = raw.find(',', pos);
      std::string t = raw.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
      pos = comma == std::string::npos ? raw.size() + 1 : comma + 1;
      if (t.empty()) {
        if (comma == std::string::npos && !out.empty()) break;
        out.push_back(t);  // the parser says what is wrong with it
        continue;
      }
      if (!options.empty() && !is_number(t)) {
        const ParamOption* hit = nullptr;
        for (const ParamOption& o : options)
          if (strcasecmp(t.c_str(), o.name) == 0) hit = &o;
        if (!hit) throw CliError(fmt::format("{}: '{}' is not an option; use {}", p.name, t, param_options_text(p.name)));
        t = fmt::format("{:g}", hit->value);
      }
      out.push_back(t);
    }
  }
  return out;
}

std::string format_param_named(const ParamInfo& p, const std::vector<double>& values) {
  std::string s = format_param_values(p, values);
  const auto& options = param_options(p.name);
  if (options.empty() || values.size() != 1) return s;
  for (const ParamOption& o : options)
    if (o.value == values[0]) return s + " (" + o.name + ")";
  return s;
}

std::string param_range_text(const ParamInfo& p) {
  std::string s = param_options(p.name).empty() ? fmt::format("range [{:g}, {:g}]", p.min, p.max)
                                                : "options " + param_options_text(p.name);
  if (!p.unit.empty()) s += " " + p.unit;
  if (!p.capacity.empty()) s += fmt::format(" (this build's capacity, {})", p.capacity);
  if (!p.is_float() && param_options(p.name).empty()) s += ", whole numbers";
  if (p.size > 1) s += fmt::format(", {} values (one sets all)", p.size);
  if (p.read_only()) s += ", read-only";
  if (p.stopped_only()) s += ", only while no run is active";
  return s;
}

}  // namespace nlsoft::console
