#include "app/tune/tune_options.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>

#include "app/text/duration.hpp"
#include "app/tune/objective.hpp"

namespace nlsoft::console {

bool set_budget(TuneOptions& o, const std::string& written) {
  // "40 runs" and "10 min" as the words come, quoted or not.
  std::string text;
  for (char c : written)
    if (c != ' ' && c != '\t') text += c;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  const std::string unit = end ? std::string(end) : "";
  if (end != text.c_str() && (unit.empty() || unit == "runs" || unit == "run")) {
    if (!(v >= 1) || v != std::floor(v) || v > 100000)
      throw std::invalid_argument(fmt::format("budget {}: a number of runs is a whole number from 1", text));
    o.budget_runs = int(v);
    return true;
  }
  // A number with a unit of time: a wall-time budget, which must be positive.
  if (end != text.c_str() && !unit.empty() && !(v > 0)) {
    try {
      text::parse_duration("1" + unit);
    } catch (const std::invalid_argument&) {
      throw std::invalid_argument(
          fmt::format("budget '{}': give runs (40) or wall time (10min, 90s); both may be given", text));
    }
    throw std::invalid_argument(fmt::format("budget '{}': a time budget must be positive, e.g. 90s or 10min", text));
  }
  try {
    o.budget_s = text::parse_duration(text);
    return false;
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument(
        fmt::format("budget '{}': give runs (40) or wall time (10min, 90s); both may be given", text));
  }
}

void validate(const TuneOptions& o) {
  if (o.dims.empty())
    throw std::invalid_argument("tune: nothing to search; give a range per parameter, e.g. Lambda=0.01..100:log");
  try {
    Objective check(o.objective);
  } catch (const ObjectiveError& e) {
    throw std::invalid_argument(e.what());
  }
  if (o.method != "bobyqa" && o.method != "neldermead")
    throw std::invalid_argument(fmt::format("method '{}': use bobyqa or neldermead (NLopt's LN_BOBYQA, LN_NELDERMEAD)",
                                            o.method));
  if (!(o.max_saturated >= 0 && o.max_saturated <= 1))
    throw std::invalid_argument(fmt::format("max_saturated {:g}: a share between 0 and 1", o.max_saturated));
  if (o.budget_runs <= 0 && o.budget_s <= 0) throw std::invalid_argument("tune: give a budget (runs or time)");
  if (o.reference.find_first_not_of(" \t") == std::string::npos && !o.reference.empty())
    throw std::invalid_argument("reference: a preset name, e.g. swirl or \"swirl hold=1\"");
  if (o.on_replays() && !o.reference.empty())
    throw std::invalid_argument("tune: replay= replays the run's own reference; reference= selects one on the "
                                "connected firmware: leave it out");
  if (!o.on_replays() && !o.model.empty())
    throw std::invalid_argument("tune: model=FILE names the model the replays run; it goes with replay=N (the "
                                "connected firmware runs the model it holds: model upload)");
  if (!o.on_replays() && !o.plant.empty())
    throw std::invalid_argument("tune: plant=FILE names the plant model the replays step in the rig's place; it goes "
                                "with replay=N");
}

TuneOptions parse_tune_words(const std::vector<std::string>& words) {
  TuneOptions o;
  bool runs_given = false;
  for (const std::string& w : words) {
    if (w == "apply") {
      o.apply = true;
      continue;
    }
    const size_t eq = w.find('=');
    const std::string key = eq == std::string::npos ? w : w.substr(0, eq);
    const std::string value = eq == std::string::npos ? "" : w.substr(eq + 1);
    auto duration = [&] {
      return value == "0" ? 0.0 : text::parse_duration(value);
    };
    if (eq == std::string::npos)
      throw std::invalid_argument(fmt::format(
          "tune: '{}' is neither NAME=LO..HI[:log|:lin] nor an option (objective= budget= reference= settle= window= "
          "seed= method= max_saturated= save= replay= model= plant= apply)",
          w));
    if (key == "objective") {
      o.objective = value;
    } else if (key == "budget") {
      runs_given |= set_budget(o, value);
    } else if (key == "reference" || key == "ref") {
      o.reference = value;
    } else if (key == "settle") {
      o.settle_s = duration();
    } else if (key == "window") {
      o.window_s = text::parse_duration(value);
      o.window_given = true;
    } else if (key == "replay") {
      char* end = nullptr;
      const long long id = value == "last" ? 0 : std::strtoll(value.c_str(), &end, 10);
      if (value != "last" && (value.empty() || *end != '\0' || id < 1))
        throw std::invalid_argument(fmt::format("replay '{}': a recorded run's id (runs list), or last", value));
      o.replay = id;
      o.replay_last = value == "last";
    } else if (key == "model") {
      if (value.empty()) throw std::invalid_argument("model=FILE: the model file the replays run");
      o.model = value;
    } else if (key == "plant") {
      if (value.empty()) throw std::invalid_argument("plant=FILE: the plant model the replays step (train --plant)");
      o.plant = value;
    } else if (key == "seed") {
      char* end = nullptr;
      o.seed = std::strtoul(value.c_str(), &end, 10);
      if (value.empty() || *end != '\0') throw std::invalid_argument(fmt::format("seed '{}': a whole number", value));
    } else if (key == "method") {
      o.method = value;
    } else if (key == "max_saturated") {
      char* end = nullptr;
      o.max_saturated = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0') throw std::invalid_argument(fmt::format("max_saturated '{}': a share, e.g. 0.5", value));
    } else if (key == "save") {
      if (value.empty()) throw std::invalid_argument("save=FILE: the file for the best set");
      o.save = value;
    } else if (value.find("..") != std::string::npos) {
      o.dims.push_back(parse_dimension(w));
    } else {
      throw std::invalid_argument(fmt::format(
          "tune: unknown option '{}'; a parameter range is NAME=LO..HI[:log|:lin], e.g. Lambda=0.01..100:log", key));
    }
  }
  // A time budget alone means: as many runs as fit.
  if (o.budget_s > 0 && !runs_given) o.budget_runs = 0;
  validate(o);
  return o;
}

const std::vector<std::string>& tune_help() {
  static const std::vector<std::string> h = {
      "tune NAME=LO..HI[:log|:lin] ...  search parameters for the lowest objective, one real run per",
      "  [objective=EXPR]          evaluation (NLopt BOBYQA): objective=\"nrmse + 0.1*u_effort\",",
      "  [budget=40|10min]         budget=40 runs and/or wall time, reference=swirl, settle=1s",
      "  [reference=NAME] [apply]  window=5s, seed=1, method=bobyqa|neldermead, max_saturated=0.5,",
      "                            save=FILE (default tune-SESSION.params); Q1=.. one element,",
      "                            Q*=0.1..1e3:log a factor on all of Q; apply keeps the best in force;",
      "                            :log searches a range uniformly in its logarithm, :lin (the default)",
      "                            in its value",
      "  [replay=N|last] [model=F] each evaluation a replay of recorded run N (last: this session's",
      "                            last run) in this process, the firmware untouched; apply then",
      "                            loads the best set onto it as params load would",
  };
  return h;
}

}  // namespace nlsoft::console
