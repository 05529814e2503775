#include "app/script/script_check.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "host/files/cli_error.hpp"
#include "app/live/live_console.hpp"
#include "app/live/param_text.hpp"
#include "app/live/reference_spec.hpp"
#include "app/live/reference_table.hpp"
#include "app/tune/live_param_source.hpp"
#include "app/tune/search_space.hpp"
#include "app/tune/tune_options.hpp"
#include "app/tune/tuner.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

// What `set NAME VALUES` (and a sweep's row) would send, checked as
// set_param parses it, plus the range PARAM_DESC gives, which the firmware
// enforces with a NACK in the same words.
void check_values(LiveConsole& console, const std::string& name, const std::vector<std::string>& tokens,
                  bool run_active) {
  const auto [info, element] = console.params().resolve(name);
  if (info.read_only()) throw CliError(fmt::format("{} is read-only", info.name));
  if (run_active && info.stopped_only())
    throw CliError(fmt::format("{} can only change while no run is active (a run started by 'start' is)", info.name));
  ParamInfo target = info;
  if (element >= 0) target.size = 1;
  const std::vector<double> v = parse_param_values(target, expand_param_tokens(target, tokens));
  for (size_t i = 0; i < v.size(); ++i) {
    if (v[i] >= double(info.min) && v[i] <= double(info.max)) continue;
    const int at = element >= 0 ? element : int(i);
    const std::string elem = info.size > 1 ? fmt::format("{}[{}]", info.name, at) : info.name;
    throw CliError(fmt::format("{} = {:g} is out of range [{:g}, {:g}]", elem, v[i], info.min, info.max));
  }
}

void check_readable(const std::string& path, const char* what) {
  if (::access(path.c_str(), R_OK) != 0) throw CliError(fmt::format("cannot read {} {}: {}", what, path, std::strerror(errno)));
}

}  // namespace

std::vector<ScriptError> check_script(const Script& script, LiveConsole& console) {
  using K = Command::Kind;
  std::vector<ScriptError> errors;
  std::vector<std::string> saved_params;  // files an earlier `params save` writes
  bool run_active = false;                // between `start` and `stop`
  for (const Command& c : script.commands) {
    try {
      switch (c.kind) {
        case K::Set: check_values(console, c.name, c.values, run_active); break;
        case K::Get: console.params().resolve(c.name); break;
        case K::Sweep:
          for (const std::string& v : c.values) check_values(console, c.name, {v}, run_active);
          break;
        case K::Ref: reference_from_spec(console.rig(), console.device().info().loop_rate_hz, c.name, c.options); break;
        case K::RefLoad: {
          RefParams tmp{};
          for (const auto& [k, v] : c.options) set_reference_key(tmp, console.device().info().loop_rate_hz, k, v);
          read_reference_csv(c.name, console.device().info().n);
          break;
        }
        case K::ParamsSave: saved_params.push_back(c.name); break;
        case K::ParamsLoad:
          // A file the script saves itself is read when the line runs.
          if (std::find(saved_params.begin(), saved_params.end(), c.name) == saved_params.end())
            console.params().load(c.name, /*dry_run=*/true);
          break;
        case K::ModelUpload: check_readable(c.name, "model"); break;
        case K::Tune: {
          const TuneOptions o = parse_tune_words(c.values);
          LiveParamSource params(console);
          SearchSpace(params, o.dims);
          if (!o.reference.empty()) tune_reference(console, o.reference);
          break;
        }
        case K::Settings:
          if (const std::string missing = console.device().settings_missing(); !missing.empty())
            throw CliError(missing);
          if (run_active && c.name != "report")
            throw CliError(fmt::format("settings {} only while no run is active (a run started by 'start' is): a "
                                       "flash erase would stall the firmware's loop",
                                       c.name));
          break;
        case K::Start: run_active = true; break;
        case K::Stop: run_active = false; break;
        default: break;
      }
    } catch (const std::exception& e) {
      errors.emplace_back(script.file, c.line, e.what());
    }
  }
  return errors;
}

}  // namespace nlsoft::console
