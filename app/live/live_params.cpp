// Parameters by name, one element or whole, and parameter files: saved,
// loaded all or nothing, compared with and reset to the rig's defaults.
#include "app/live/live_params.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <map>
#include <sstream>

#include "host/files/cli_error.hpp"
#include "host/files/input_file.hpp"
#include "app/link/param_resolve.hpp"
#include "app/live/param_defaults.hpp"
#include "app/live/param_text.hpp"
#include "app/live/params_file.hpp"
#include "host/files/printable.hpp"
#include "app/record/run_edit.hpp"

namespace nlsoft::console {

using host::CliError;
using host::Rig;
using host::kParamsFile;
using host::printable;
using host::printable_excerpt;
using host::read_input_file;

namespace p = nlsoft::protocol;

std::pair<ParamInfo, int> LiveParams::resolve(const std::string& name) const {
  return resolve_param(*device_.catalog(), name);
}

std::vector<double> LiveParams::set(const std::string& name, const std::vector<std::string>& values) {
  const auto [pinfo, element] = resolve(name);
  const ParamInfo* info = &pinfo;
  std::vector<double> v;
  if (element >= 0) {
    ParamInfo one = *info;
    one.size = 1;
    const std::vector<double> x = parse_param_values(one, expand_param_tokens(one, values));
    v = device_.get(*info);
    v[size_t(element)] = x[0];
  } else {
    v = parse_param_values(*info, expand_param_tokens(*info, values));
  }
  return apply(*info, v);
}

std::vector<double> LiveParams::apply(const ParamInfo& info, const std::vector<double>& values) {
  const std::vector<double> echoed = device_.set(info, values);
  {
    std::lock_guard<std::mutex> lock(mu_);
    edits_.erase(std::remove_if(edits_.begin(), edits_.end(), [&](const auto& e) { return e.first.name == info.name; }),
                 edits_.end());
    edits_.emplace_back(info, echoed);
  }
  run_.log_change(info.name, format_param_values(info, echoed));
  return echoed;
}

LiveParams::Edits LiveParams::edits() const {
  std::lock_guard<std::mutex> lock(mu_);
  return edits_;
}

std::pair<ParamInfo, std::vector<double>> LiveParams::get(const std::string& name) {
  const ParamInfo info = resolve(name).first;
  return {info, device_.get(info)};
}

void LiveParams::save(const std::string& path) { write_params_file(path, device_.info(), device_.get_all()); }

std::vector<std::string> LiveParams::load(const std::string& path, bool dry_run) {
  std::istringstream in(read_input_file(path, kParamsFile));
  const auto cat = device_.catalog();
  std::string line;
  int lineno = 0;
  // Parse and check the whole file before sending anything.
  std::vector<WantedValue> wanted;
  // A parameter named twice would end with whichever value differs from
  // the one in force: refused, nothing sent.
  std::map<std::string, int> first_line;
  while (std::getline(in, line)) {
    ++lineno;
    std::istringstream ls(line);
    std::string name;
    if (!(ls >> name) || name[0] == '#') continue;
    const ParamInfo* info = cat->find(name);
    if (!info) throw CliError(fmt::format("{}:{}: unknown parameter '{}'; the firmware has: {}", path, lineno,
                                            printable_excerpt(name), cat->names()));
    if (const auto [at, fresh] = first_line.emplace(info->name, lineno); !fresh)
      throw CliError(fmt::format("{}:{}: {} is named a second time (first at line {}): which value should be in force? "
                                 "nothing applied",
                                 path, lineno, printable(info->name), at->second));
    std::vector<std::string> tokens;
    std::string t;
    while (ls >> t) tokens.push_back(t);
    try {
      wanted.push_back({*info, parse_param_values(*info, expand_param_tokens(*info, tokens)), fmt::format("{}:{}", path, lineno)});
    } catch (const CliError& e) {
      throw CliError(fmt::format("{}:{}: {}", path, lineno, e.what()));
    }
  }
  return apply_values(wanted, dry_run);
}

std::vector<LiveParams::WantedValue> LiveParams::defaults_wanted() const {
  const p::Info info = device_.info();
  const Rig& r = rig_.rig();
  if (r.m() != info.m || r.n() != info.n)
    throw CliError(fmt::format("rig file {} has m={} n={}; the firmware runs m={} n={}", r.file, r.m(), r.n(), info.m,
                               info.n));
  const auto defaults = firmware_defaults(r);
  std::vector<WantedValue> wanted;
  for (const ParamInfo& pi : device_.catalog()->all()) {
    const auto d = defaults.find(pi.id);
    if (d == defaults.end() || pi.read_only() || d->second.size() != pi.size) continue;
    wanted.push_back({pi, d->second, "default"});
  }
  return wanted;
}

std::vector<std::string> LiveParams::diff_from_defaults() {
  std::vector<std::string> lines;
  for (const WantedValue& w : defaults_wanted()) {
    const std::vector<double> now = device_.get(w.info);
    if (same_param_values(now, w.values)) continue;
    lines.push_back(fmt::format("{}: {} (default {})", w.info.name, format_param_named(w.info, now),
                                format_param_named(w.info, w.values)));
  }
  return lines;
}

std::vector<std::string> LiveParams::reset_to_defaults() { return apply_values(defaults_wanted(), false); }

bool same_param_values(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (float(a[i]) != float(b[i])) return false;
  return true;
}

std::vector<std::string> LiveParams::apply_values(const std::vector<WantedValue>& wanted, bool dry_run) {
  struct Change {
    const WantedValue* want;
    std::vector<double> from;
  };
  std::vector<Change> changes;
  std::vector<std::string> diff;
  for (const WantedValue& w : wanted) {
    const std::vector<double> from = device_.get(w.info);
    if (same_param_values(from, w.values)) continue;
    diff.push_back(fmt::format("{}: {} -> {}", w.info.name, format_param_values(w.info, from),
                               format_param_values(w.info, w.values)));
    changes.push_back({&w, from});
  }
  if (dry_run) return diff;
  for (size_t i = 0; i < changes.size(); ++i) {
    try {
      apply(changes[i].want->info, changes[i].want->values);
    } catch (const std::exception& e) {
      // All or nothing, like PARAM_SET itself: put back what went through.
      size_t restored = 0;
      for (size_t j = i; j-- > 0;) {
        try {
          apply(changes[j].want->info, changes[j].from);
          ++restored;
        } catch (...) {
        }
      }
      throw CliError(fmt::format("{}: {}; {} earlier change{} rolled back, nothing changed", changes[i].want->origin,
                                 e.what(), restored, restored == 1 ? "" : "s"));
    }
  }
  return diff;
}

}  // namespace nlsoft::console
