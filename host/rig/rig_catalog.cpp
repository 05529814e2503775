#include "host/rig/rig_catalog.hpp"

#include <algorithm>
#include <filesystem>
#include <map>

#include "host/files/cli_error.hpp"
#include "host/files/input_file.hpp"
#include "host/paths/install_paths.hpp"
#include "shared/platform_id.hpp"

namespace nlsoft::console {

namespace {

bool names_a_file(const std::string& arg) {
  return arg.find('/') != std::string::npos ||
         (arg.size() > 5 && arg.compare(arg.size() - 5, 5, ".toml") == 0);
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

}  // namespace

std::vector<std::string> rig_names() {
  const Lookup dir = find_rigs_dir();
  std::vector<std::string> names;
  if (dir.found.empty()) return names;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir.found, ec))
    if (e.path().extension() == ".toml") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string rig_path(const std::string& arg) {
  if (names_a_file(arg)) {
    std::error_code ec;
    if (!std::filesystem::exists(arg, ec)) throw CliError("rig file '" + arg + "' does not exist");
    check_input_file(arg, kRigFile);  // a device, a FIFO, a folder: said as such
    return arg;
  }
  const Lookup dir = find_rigs_dir();
  if (dir.found.empty())
    throw CliError("unknown rig '" + arg + "': no rigs folder found; looked in:" + dir.tried_lines() +
                   "\n(give a rig file's path, or set NLSOFT_RIGS)");
  const std::string path = dir.found + "/" + arg + ".toml";
  if (!std::filesystem::is_regular_file(path))
    throw CliError("unknown rig '" + arg + "'; rigs in " + dir.found + ": " + joined(rig_names()) +
                   " (or give a rig file's path)");
  return path;
}

Rig load_rig_arg(const std::string& arg) {
  const std::string path = rig_path(arg);
  try {
    return load_rig(path);
  } catch (const RigError& e) {
    throw CliError(e.what());
  }
}

std::string rig_name_of_platform(uint8_t info_platform) {
  // Read once per process: the console asks on every redraw of a firmware
  // too old to send RIG_INFO, and the shipped rigs do not change under it.
  static const std::map<uint8_t, std::string> numbered = [] {
    std::map<uint8_t, std::string> m;
    for (const std::string& name : rig_names()) {
      // A shipped file that does not load names no rig here; `rig check` says why.
      try {
        const Rig rig = load_rig_arg(name);
        if (rig.info_platform != uint8_t(PlatformId::Custom)) m.emplace(rig.info_platform, name);
      } catch (const CliError&) {
      }
    }
    return m;
  }();
  const auto it = numbered.find(info_platform);
  return it == numbered.end() ? std::string() : it->second;
}

CLI::Validator rig_arg_validator() {
  return CLI::Validator(
      [](std::string& arg) -> std::string {
        try {
          rig_path(arg);
        } catch (const CliError& e) {
          return e.what();
        }
        return {};
      },
      "RIG");
}

std::string rig_arg_help() {
  const std::vector<std::string> names = rig_names();
  return "NAME|PATH" + (names.empty() ? std::string() : " (" + joined(names) + ")");
}

}  // namespace nlsoft::console
