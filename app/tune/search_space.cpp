#include "app/tune/search_space.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "host/files/cli_error.hpp"
#include "shared/fixed_math.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

double number(const std::string& text, const std::string& spec) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
    throw std::invalid_argument(
        fmt::format("--param {}: '{}' is not a number; write NAME=LO..HI or NAME=LO..HI:log, e.g. Lambda=0.01..100:log",
                    spec, text));
  return v;
}

double clamp01(double u) { return std::min(1.0, std::max(0.0, u)); }

}  // namespace

Dimension parse_dimension(const std::string& spec) {
  Dimension d;
  d.spec = spec;
  const size_t eq = spec.find('=');
  if (eq == std::string::npos || eq == 0)
    throw std::invalid_argument(
        fmt::format("--param {}: expected NAME=LO..HI[:log|:lin], e.g. Lambda=0.01..100:log or Q1=1e5..1e7:log", spec));
  d.name = spec.substr(0, eq);
  std::string range = spec.substr(eq + 1);
  const size_t colon = range.rfind(':');
  if (colon != std::string::npos) {
    const std::string scale = range.substr(colon + 1);
    if (scale == "log") d.log = true;
    else if (scale != "lin")
      throw std::invalid_argument(fmt::format("--param {}: ':{}' is not a scale; use :log or :lin (the default)", spec, scale));
    range = range.substr(0, colon);
  }
  const size_t dots = range.find("..");
  if (dots == std::string::npos)
    throw std::invalid_argument(fmt::format("--param {}: the range needs LO..HI, e.g. {}=0.01..100:log", spec, d.name));
  d.lo = number(range.substr(0, dots), spec);
  d.hi = number(range.substr(dots + 2), spec);
  if (!(d.lo < d.hi)) throw std::invalid_argument(fmt::format("--param {}: LO must be below HI", spec));
  if (d.log && !(d.lo > 0))
    throw std::invalid_argument(fmt::format("--param {}: a :log range needs LO > 0 (got {:g})", spec, d.lo));
  return d;
}

SearchSpace::SearchSpace(ParamSource& params, std::vector<Dimension> dims) : dims_(std::move(dims)) {
  if (dims_.empty()) throw CliError("tune: give at least one --param NAME=LO..HI[:log|:lin], e.g. --param Lambda=0.01..100:log");
  std::vector<std::string> seen;
  for (const Dimension& d : dims_) {
    const bool scale = !d.name.empty() && d.name.back() == '*';
    const std::string name = scale ? d.name.substr(0, d.name.size() - 1) : d.name;
    std::pair<ParamInfo, int> resolved;
    try {
      resolved = params.resolve(name);
    } catch (const CliError& e) {
      throw CliError(fmt::format("--param {}: {}", d.spec, e.what()));
    }
    const auto& [info, element] = resolved;
    if (scale && element >= 0)
      throw CliError(fmt::format("--param {}: a factor (NAME*) scales a whole parameter; write {}*", d.spec, info.name));
    if (info.read_only()) throw CliError(fmt::format("--param {}: {} is read-only", d.spec, info.name));
    if (info.type != protocol::ParamType::F32 && d.log && d.lo < 1)
      throw CliError(fmt::format("--param {}: {} takes whole numbers; a :log range of it starts at 1 or above", d.spec,
                                 info.name));
    const std::string key = element >= 0 ? fmt::format("{}[{}]", info.name, element) : info.name;
    for (const std::string& s : seen)
      if (s == key || s == info.name || (element < 0 && s.rfind(info.name + "[", 0) == 0))
        throw CliError(fmt::format("--param {}: {} is already searched by another --param", d.spec, key));
    seen.push_back(key);
    size_t p = 0;
    while (p < original_.size() && original_[p].first.name != info.name) ++p;
    if (p == original_.size()) original_.emplace_back(info, params.in_force(info));
    const std::vector<double>& now = original_[p].second;
    // Ranges inside the table's: the firmware would refuse every candidate
    // outside, and the search would spend its budget learning that.
    double lo = d.lo, hi = d.hi;
    if (scale) {
      double big = 0;
      for (double v : now) big = std::max(big, std::fabs(v));
      if (big == 0)
        throw CliError(fmt::format("--param {}: {} is 0 everywhere; a factor on it changes nothing (search {} itself)",
                                   d.spec, info.name, info.name));
      lo = hi = now[0] * d.lo;
      for (double v : now)
        for (double f : {d.lo, d.hi}) lo = std::min(lo, v * f), hi = std::max(hi, v * f);
    }
    if (lo < double(info.min) || hi > double(info.max))
      throw CliError(fmt::format("--param {}: {} ranges over [{:g}, {:g}], outside {}'s range [{:g}, {:g}]", d.spec,
                                 scale ? "the scaled value" : info.name, lo, hi, info.name, info.min, info.max));
    targets_.push_back({p, element, scale});
  }
  const std::vector<double> s = start();
  for (size_t i = 0; i < dims_.size(); ++i) {
    const Target& t = targets_[i];
    if (t.scale) continue;
    const auto& v = original_[t.param].second;
    const double now = t.element >= 0 ? v[size_t(t.element)] : v[0];
    if (now < dims_[i].lo || now > dims_[i].hi)
      clamped_.push_back(fmt::format("{} is {:g}, outside {}; the search starts at {:g}", dims_[i].name, now,
                                     dims_[i].spec.substr(dims_[i].spec.find('=') + 1), value(i, s[i])));
  }
}

std::vector<double> SearchSpace::start() const {
  std::vector<double> u;
  for (size_t i = 0; i < dims_.size(); ++i) {
    const Dimension& d = dims_[i];
    const Target& t = targets_[i];
    const auto& v = original_[t.param].second;
    double x = 1.0;  // a factor starts at the values in force
    if (!t.scale) {
      if (t.element >= 0) {
        x = v[size_t(t.element)];
      } else {
        // One value for several elements: their geometric mean on a log
        // range, else their mean.
        double sum = 0, logsum = 0;
        for (double e : v) sum += e, logsum += fixed_math::log(std::max(e, 1e-300));
        x = d.log ? fixed_math::exp(logsum / double(v.size())) : sum / double(v.size());
      }
    }
    x = std::min(d.hi, std::max(d.lo, x));
    u.push_back(d.log ? fixed_math::log(x / d.lo) / fixed_math::log(d.hi / d.lo) : (x - d.lo) / (d.hi - d.lo));
  }
  return u;
}

double SearchSpace::value(size_t i, double unit) const {
  const Dimension& d = dims_[i];
  const double u = clamp01(unit);
  double x = d.log ? d.lo * fixed_math::pow(d.hi / d.lo, u) : d.lo + u * (d.hi - d.lo);
  const ParamInfo& info = original_[targets_[i].param].first;
  if (!targets_[i].scale && info.type != protocol::ParamType::F32) x = std::round(x);
  return std::min(d.hi, std::max(d.lo, x));
}

std::vector<SearchSpace::Write> SearchSpace::writes(const std::vector<double>& unit) const {
  std::vector<Write> out = original_;
  // Factors first, so an element named on its own keeps its own value.
  for (int pass = 0; pass < 2; ++pass)
    for (size_t i = 0; i < dims_.size(); ++i) {
      const Target& t = targets_[i];
      if (t.scale != (pass == 0)) continue;
      std::vector<double>& v = out[t.param].second;
      const double x = value(i, unit[i]);
      if (t.scale)
        for (size_t e = 0; e < v.size(); ++e) v[e] = original_[t.param].second[e] * x;
      else if (t.element >= 0)
        v[size_t(t.element)] = x;
      else
        std::fill(v.begin(), v.end(), x);
    }
  return out;
}

std::string SearchSpace::describe(const std::vector<double>& unit) const {
  std::string s;
  for (size_t i = 0; i < dims_.size(); ++i) s += fmt::format("{}{}={:.4g}", s.empty() ? "" : " ", dims_[i].name, value(i, unit[i]));
  return s;
}

std::string SearchSpace::text() const {
  std::string s;
  for (const Dimension& d : dims_) s += (s.empty() ? "" : " ") + d.spec;
  return s;
}

}  // namespace nlsoft::console
