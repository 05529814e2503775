#include "app/live/params_file.hpp"

#include <fmt/format.h>

#include "app/record/utc_time.hpp"
#include "host/files/cli_error.hpp"
#include "host/files/output_file.hpp"
#include "host/files/printable.hpp"

namespace nlsoft::console {

using host::CliError;
using host::OutputFile;
using host::printable;

namespace {

// A name `params load` reads back as the same one word.
bool is_file_token(const std::string& name) {
  if (name.empty() || name[0] == '#') return false;
  for (unsigned char c : name)
    if (c <= ' ' || c == 0x7f) return false;
  return true;
}

}  // namespace

void write_params_file(const std::string& path, const protocol::Info& info,
                       const std::vector<std::pair<ParamInfo, std::vector<double>>>& all) {
  // A file holds what was measured, one parameter a line, whatever the
  // firmware's words contain: its name is escaped where it is decoded (no
  // newline can plant a line), and a parameter name that would not read
  // back as one token (a space, a '#') is refused before a byte is written.
  for (const auto& [pi, v] : all)
    if (!is_file_token(pi.name))
      throw CliError(fmt::format("cannot save parameter '{}' to {}: its name would not read back as one word; "
                                 "nothing written",
                                 printable(pi.name), path));
  OutputFile out(path);
  fmt::print(out.get(), "# nlsoft parameters: {} {}.{}.{}, platform {}, saved {}\n", info.firmware, info.fw_major,
             info.fw_minor, info.fw_patch, int(info.platform), utc_now());
  fmt::print(out.get(), "# NAME VALUES...  (load with `params load FILE`)\n");
  for (const auto& [pi, v] : all) fmt::print(out.get(), "{} {}\n", pi.name, format_param_values(pi, v));
  out.commit();
}

}  // namespace nlsoft::console
