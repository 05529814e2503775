#include "app/link/param_catalog.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <strings.h>

#include "host/files/cli_error.hpp"
#include "app/simulate/param_args.hpp"
#include "app/link/link_error.hpp"
#include "host/files/printable.hpp"

namespace nlsoft::console {

using host::CliError;
using host::printable;

namespace proto = nlsoft::protocol;

ParamInfo param_info_from(const proto::ParamDesc& d) {
  ParamInfo i;
  i.index = d.index;
  i.id = d.id;
  i.type = proto::ParamType(d.type);
  i.size = d.size;
  i.access = d.access;
  i.min = d.min;
  i.max = d.max;
  // The firmware's words, escaped where they become strings: a name or a
  // unit cannot reach a terminal or a parameter file raw.
  i.unit = printable(d.unit);
  i.name = printable(d.name);
  return i;
}

void apply_capacity(std::vector<ParamInfo>& params, unsigned max_n, unsigned max_nc) {
  for (ParamInfo& p : params) {
    const bool horizon = p.name == "N" || p.name == "N1";
    if (!horizon && p.name != "Nc") continue;
    const unsigned cap = horizon ? max_n : max_nc;
    if (cap == 0 || double(cap) >= double(p.max)) continue;
    p.max = float(cap);
    p.capacity = horizon ? "max_n" : "max_nc";
  }
}

const ParamInfo* ParamCatalog::find(const std::string& name) const {
  for (const ParamInfo& p : params_)
    if (p.name == name) return &p;
  for (const ParamInfo& p : params_)
    if (strcasecmp(p.name.c_str(), name.c_str()) == 0) return &p;
  return nullptr;
}

const ParamInfo* ParamCatalog::find_id(uint16_t id) const {
  for (const ParamInfo& p : params_)
    if (p.id == id) return &p;
  return nullptr;
}

const ParamInfo& ParamCatalog::require(const std::string& name) const {
  const ParamInfo* p = find(name);
  if (!p) {
    if (params_.empty()) throw CliError("the firmware has no parameter list (not connected yet?)");
    throw CliError(fmt::format("unknown parameter '{}'; the firmware has: {}", name, names()));
  }
  return *p;
}

std::string ParamCatalog::names() const {
  std::string s;
  for (const ParamInfo& p : params_) s += (s.empty() ? "" : ", ") + p.name;
  return s;
}

std::vector<double> parse_param_values(const ParamInfo& p, const std::vector<std::string>& tokens) {
  return parse_param_numbers(p.name, tokens, p.size, p.is_float());
}

void encode_param_values(const ParamInfo& p, const std::vector<double>& values, uint32_t* words) {
  for (size_t i = 0; i < values.size(); ++i) {
    if (p.is_float()) {
      const float f = float(values[i]);
      std::memcpy(&words[i], &f, 4);
    } else {
      words[i] = values[i] < 0 ? 0u : values[i] > 4294967295.0 ? 0xFFFFFFFFu : uint32_t(values[i]);
    }
  }
}

std::vector<double> decode_param_values(const ParamInfo& p, const uint32_t* words, uint8_t count) {
  std::vector<double> out(count);
  for (uint8_t i = 0; i < count; ++i) {
    if (p.is_float()) {
      float f;
      std::memcpy(&f, &words[i], 4);
      out[i] = double(f);
    } else {
      out[i] = double(words[i]);
    }
  }
  return out;
}

std::string format_param_values(const ParamInfo& p, const std::vector<double>& values) {
  std::string s;
  for (double v : values) {
    if (!s.empty()) s += ' ';
    // Six digits where they read back as the same float, else the shortest
    // text that does: a saved set loads without a spurious change.
    if (p.is_float()) {
      const float f = float(v);
      const std::string g = fmt::format("{:g}", f);
      s += std::strtof(g.c_str(), nullptr) == f ? g : fmt::format("{}", f);
    } else {
      s += fmt::format("{}", uint64_t(v));
    }
  }
  return s;
}

std::string describe_param_refusal(const ParamInfo& p, const proto::Nack& nack, const std::vector<double>& sent) {
  const bool has_elem = nack.element != proto::kNoField;
  const std::string elem = has_elem && p.size > 1 ? fmt::format("{}[{}]", p.name, nack.element) : p.name;
  const double v = has_elem && nack.element < sent.size() ? sent[nack.element] : sent.size() == 1 ? sent[0] : 0.0;
  switch (proto::StatusCode(nack.status)) {
    case proto::StatusCode::OutOfRange:
      return fmt::format("{} = {:g} is out of range [{:g}, {:g}]", elem, v, p.min, p.max);
    case proto::StatusCode::NotFinite:
      if (std::isfinite(v) && std::fabs(v) > double(FLT_MAX))
        return fmt::format("{} = {:g} overflows a float32 (the firmware's number type): its magnitude must be at most "
                           "{:g}", elem, v, double(FLT_MAX));
      return fmt::format("{} must be a finite number", elem);
    case proto::StatusCode::WrongSize: return fmt::format("{} takes {} values", p.name, p.size);
    case proto::StatusCode::ReadOnly: return fmt::format("{} is read-only", p.name);
    case proto::StatusCode::WrongState: return fmt::format("{} can only change while no run is active", p.name);
    case proto::StatusCode::Inconsistent:
      return fmt::format("{}{} = {} breaks a rule between parameters (e.g. Nc <= N, u_min < u_max)", elem,
                         has_elem ? "" : "", has_elem ? fmt::format("{:g}", v) : format_param_values(p, sent));
    case proto::StatusCode::TooLarge:
      if (!p.capacity.empty())
        return fmt::format("{} = {:g} is over this firmware build's capacity: at most {:g} ({} in INFO)", elem, v, p.max,
                           p.capacity);
      return fmt::format("{} = {:g} exceeds what this firmware build can hold", elem, v);
    default: return fmt::format("{} refused: {}", p.name, status_words(nack.status));
  }
}

}  // namespace nlsoft::console
