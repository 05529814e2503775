#include "app/simulate/param_args.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "host/files/cli_error.hpp"

namespace nlsoft::console {

std::string known_param_names() {
  std::string s;
  for (const ParamDesc& d : kParamTable) s += (s.empty() ? "" : ", ") + std::string(d.name);
  return s;
}

ParamWrite parse_param_write(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw CliError(fmt::format("'{}': expected NAME=VALUE[,VALUE...], e.g. Q=1e6,2e6,1e6", text));
  const std::string name = text.substr(0, eq);
  const ParamDesc* d = find_param(name.c_str());
  if (!d) throw CliError(fmt::format("unknown parameter '{}'; known: {}", name, known_param_names()));
  ParamWrite w{d->id, {}};
  std::string rest = text.substr(eq + 1);
  size_t pos = 0;
  while (true) {
    const size_t comma = rest.find(',', pos);
    const std::string item = rest.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    if (item.empty()) throw CliError(fmt::format("'{}': empty value at position {}", text, w.values.size()));
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || *end != '\0')
      throw CliError(fmt::format("'{}': '{}' is not a number", text, item));
    w.values.push_back(float(v));
    if (comma == std::string::npos) break;
    pos = comma + 1;
  }
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
