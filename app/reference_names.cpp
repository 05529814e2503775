#include "app/reference_names.hpp"

#include <fmt/format.h>

#include "host/files/cli_error.hpp"
#include "host/rig/rig_reference.hpp"

namespace nlsoft::console {

using host::CliError;
using host::Rig;
using host::rig_reference;

namespace {

struct Named {
  const char* name;
  RefKind kind;
};
constexpr Named kNames[] = {{"infinity", RefKind::Infinity}, {"pringle", RefKind::Pringle},
                            {"diagonal", RefKind::Diagonal}, {"swirl", RefKind::Swirl},
                            {"steps", RefKind::Step},        {"hold", RefKind::Hold}};

}  // namespace

const std::vector<std::string>& reference_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const Named& n : kNames) v.emplace_back(n.name);
    return v;
  }();
  return names;
}

namespace {

RefKind kind_of(const std::string& name) {
  for (const Named& n : kNames)
    if (name == n.name) return n.kind;
  std::string known;
  for (const auto& n : reference_names()) known += (known.empty() ? "" : ", ") + n;
  throw CliError(fmt::format("unknown reference '{}'; known: {}", name, known));
}

}  // namespace

RefParams reference_by_name(const Rig& rig, const std::string& name) { return rig_reference(rig, kind_of(name)); }

std::string default_reference(const Rig& rig) {
  for (const Named& n : kNames)
    if (n.kind == rig.reference.kind) return n.name;
  return "hold";
}

}  // namespace nlsoft::console
