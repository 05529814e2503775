#include "app/link/param_resolve.hpp"

#include <fmt/format.h>

#include <cctype>
#include <cstdlib>

#include "host/files/cli_error.hpp"

namespace nlsoft::console {

using host::CliError;

namespace {

// "Q[1]" -> ("Q", 1); "Q" -> ("Q", -1).
std::pair<std::string, int> split_element(const std::string& name) {
  const size_t open = name.find('[');
  if (open != std::string::npos && name.back() == ']') {
    const std::string idx = name.substr(open + 1, name.size() - open - 2);
    char* end = nullptr;
    const long i = std::strtol(idx.c_str(), &end, 10);
    if (idx.empty() || *end != '\0' || i < 0) throw CliError(fmt::format("'{}': bad element index", name));
    return {name.substr(0, open), int(i)};
  }
  return {name, -1};
}

}  // namespace

std::pair<ParamInfo, int> resolve_param(const ParamCatalog& cat, const std::string& name) {
  auto [base, element] = split_element(name);
  const ParamInfo* info = cat.find(base);
  if (!info && element < 0) {
    // "Q0" = Q[0], as in `sweep Q0 1e5 1e6`.
    size_t d = base.size();
    while (d > 0 && std::isdigit(static_cast<unsigned char>(base[d - 1]))) --d;
    if (d > 0 && d < base.size() && cat.find(base.substr(0, d))) {
      element = std::atoi(base.c_str() + d);
      info = cat.find(base.substr(0, d));
    }
  }
  if (!info) cat.require(base);  // throws with the known names
  if (element >= int(info->size))
    throw CliError(fmt::format("{}[{}]: {} has {} element{} (0..{})", info->name, element, info->name, info->size,
                               info->size == 1 ? "" : "s", info->size - 1));
  return {*info, element};
}

}  // namespace nlsoft::console
