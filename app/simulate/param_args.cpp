#include "app/simulate/param_args.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cfloat>
#include <limits>
#include <cmath>
#include <cstdlib>

#include "host/files/cli_error.hpp"

namespace nlsoft::console {

using host::CliError;

std::string known_param_names() {
  std::string s;
  for (const ParamDesc& d : kParamTable) s += (s.empty() ? "" : ", ") + std::string(d.name);
  return s;
}

std::vector<double> parse_param_numbers(const std::string& name, const std::vector<std::string>& tokens, size_t count,
                                        bool is_float) {
  std::vector<double> out;
  for (const std::string& raw : tokens) {
    // "1e6,2e6,1e6" and "1e6 2e6 1e6" both read naturally; accept both.
    size_t pos = 0;
    while (pos <= raw.size()) {
      const size_t comma = raw.find(',', pos);
      const std::string t = raw.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
      pos = comma == std::string::npos ? raw.size() + 1 : comma + 1;
      if (t.empty()) {
        if (comma == std::string::npos && !out.empty()) break;
        throw CliError(fmt::format("{}: empty value in '{}'", name, raw));
      }
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(t.c_str(), &end);
      if (end == t.c_str() || *end != '\0') throw CliError(fmt::format("{}: '{}' is not a number", name, t));
      if (!std::isfinite(v)) throw CliError(fmt::format("{}: '{}' is not a finite number", name, t));
      // Nor may a value too small for the number type arrive as 0.
      if ((errno == ERANGE && std::fabs(v) <= DBL_MIN) || (is_float && v != 0 && float(v) == 0.0f))
        throw CliError(fmt::format("{}: '{}' underflows a float32 (the firmware's number type) to 0: a magnitude "
                                   "other than 0 must be at least {:g}",
                                   name, t, double(std::numeric_limits<float>::denorm_min())));
      // The firmware keeps float32: a larger value would arrive as infinity.
      if (is_float && std::fabs(v) > double(FLT_MAX))
        throw CliError(fmt::format("{}: '{}' overflows a float32 (the firmware's number type): its magnitude must be "
                                   "at most {:g}", name, t, double(FLT_MAX)));
      if (!is_float && (v != std::floor(v) || v < 0))
        throw CliError(fmt::format("{}: '{}' must be a whole number >= 0", name, t));
      out.push_back(v);
    }
  }
  // One value stands for every element (`set Lambda 0.5`, --set Lambda=0.5).
  if (out.size() == 1 && count > 1) out.assign(count, out[0]);
  if (out.size() != count)
    throw CliError(fmt::format("{} takes {} value{}, got {}", name, count, count == 1 ? "" : "s", out.size()));
  return out;
}

ParamWrite parse_param_write(const std::string& text, int m, int n) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw CliError(fmt::format("'{}': expected NAME=VALUE[,VALUE...], e.g. Q=1e6,2e6,1e6", text));
  const std::string name = text.substr(0, eq);
  const ParamDesc* d = find_param(name.c_str());
  if (!d) throw CliError(fmt::format("unknown parameter '{}'; known: {}", name, known_param_names()));
  ParamWrite w{d->id, {}};
  for (double v : parse_param_numbers(d->name, {text.substr(eq + 1)}, size_t(param_count(*d, m, n)),
                                      d->type == ParamType::F32))
    w.values.push_back(float(v));
  return w;
}

std::string describe_refusal(const ParamWrite& w, const ParamResult& r, int m, int n) {
  const ParamDesc& d = kParamTable[uint8_t(w.id)];
  const int want = param_count(d, m, n);
  const std::string elem = r.index >= 0 ? fmt::format("{}[{}]", d.name, r.index) : std::string(d.name);
  const float v = r.index >= 0 && size_t(r.index) < w.values.size() ? w.values[size_t(r.index)] : 0.0f;
  switch (r.status) {
    case Status::WrongSize:
      return fmt::format("{} takes {} value{} here ({}), got {}", d.name, want, want == 1 ? "" : "s",
                         d.size == ParamSize::PerOutput ? "one per output"
                         : d.size == ParamSize::PerInput ? "one per actuator"
                                                          : "a scalar",
                         w.values.size());
    case Status::NotFinite: return fmt::format("{} must be a finite number", elem);
    case Status::OutOfRange:
      return fmt::format("{} = {} is out of range [{:g}, {:g}]{}", elem, v, d.min, d.max,
                         d.type != ParamType::F32 ? " (whole numbers)" : "");
    case Status::TooLarge: return fmt::format("{} = {:g} exceeds what this build can hold", elem, v);
    case Status::Inconsistent:
      return fmt::format("{} would break a rule between parameters (Nc <= N, N1 <= N, u_min < u_max){}", d.name,
                         r.index >= 0 ? fmt::format(" at element {}", r.index) : "");
    default: return fmt::format("{} refused: {}", d.name, status_name(r.status));
  }
}

void apply_param_writes(Params<HostCapacity>& P, const std::vector<ParamWrite>& writes, int m, int n) {
  for (const ParamWrite& w : writes) {
    const ParamResult r = set_param(P, w.id, w.values.data(), int(w.values.size()), m, n);
    if (r.status != Status::Ok) throw CliError(describe_refusal(w, r, m, n));
  }
}

}  // namespace nlsoft::console
