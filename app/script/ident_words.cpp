#include "app/script/ident_words.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "host/files/cli_error.hpp"

namespace nlsoft::console {

using host::CliError;

IdentWords ident_words(const Command& c) {
  IdentWords w;
  w.signal = c.name;
  w.duration = c.values.empty() ? "" : c.values[0];
  for (const auto& [k, v] : c.options) {
    try {
      size_t used = 0;
      if (k == "seed") {
        const unsigned long long x = std::stoull(v, &used);
        if (used != v.size() || x > 0xFFFFFFFFull) throw std::out_of_range(v);
        w.seed = uint32_t(x);
      } else if (k == "amplitude") {
        w.amplitude = std::stod(v, &used);
      } else if (k == "decimation") {
        w.decimation = std::stoi(v, &used);
        if (w.decimation < 1) throw std::out_of_range(v);
      } else if (k == "band") {
        w.band = v, used = v.size();
      } else if (k == "joint") {
        w.joint = true, used = v.size();
      } else if (k == "mixed") {
        w.mixed = true, used = v.size();
      } else if (k == "y_offset") {
        used = v.size();  // the capture's, not the excitation's (script_runner merges it)
      }
      if (used != v.size()) throw std::invalid_argument(v);
    } catch (const std::logic_error&) {
      throw CliError(fmt::format("ident: {}={} is not a valid {}", k, v,
                                 k == "seed" ? "seed (0..4294967295)" : k == "decimation" ? "decimation (1..65535)" : "number"));
    }
  }
  return w;
}

}  // namespace nlsoft::console
