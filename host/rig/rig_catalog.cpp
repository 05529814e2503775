#include "host/rig/rig_catalog.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include "host/files/cli_error.hpp"
#include "host/files/input_file.hpp"
#include "host/files/printable.hpp"
#include "host/paths/install_paths.hpp"
#include "shared/platform_id.hpp"

namespace nlsoft::host {

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

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A rig by name from $NLSOFT_RIGS is said where it is used: that folder
// comes before the shipped rigs, so `hasel` may be another file than the
// shipped hasel. Said once a process, and not for a copy of the shipped
// file (the tests' and the docs' NLSOFT_RIGS is the source tree's rigs/).
void say_from_env(const std::string& name, const std::string& path, const std::string& env_dir,
                  const std::vector<RigsFolder>& folders) {
  static std::mutex m;
  static std::set<std::string> said;
  const std::lock_guard<std::mutex> lock(m);
  if (!said.insert(path).second) return;
  for (const RigsFolder& f : folders)
    if (!f.from_env && std::filesystem::is_regular_file(f.dir + "/" + name + ".toml") &&
        file_bytes(f.dir + "/" + name + ".toml") == file_bytes(path))
      return;
  std::fprintf(stderr, "rig '%s' is %s, from the folder $NLSOFT_RIGS names (%s)\n", printable(name).c_str(),
               printable(path).c_str(), printable(env_dir).c_str());
}

}  // namespace

std::vector<std::string> rig_names() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const RigsFolder& f : rigs_folders())
    for (const auto& e : std::filesystem::directory_iterator(f.dir, ec))
      if (e.path().extension() == ".toml") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

namespace {
std::atomic<long> g_resolved{0};
}  // namespace

long rig_args_resolved() { return g_resolved.load(); }

std::string rig_path(const std::string& arg) {
  ++g_resolved;
  if (names_a_file(arg)) {
    std::error_code ec;
    if (!std::filesystem::exists(arg, ec)) throw CliError("rig file '" + arg + "' does not exist");
    check_input_file(arg, kRigFile);  // a device, a FIFO, a folder: said as such
    return arg;
  }
  const std::vector<RigsFolder> folders = rigs_folders();
  if (folders.empty())
    throw CliError("unknown rig '" + printable(arg) + "': no rigs folder found; looked in:" +
                   find_rigs_dir().tried_lines() + "\n(give a rig file's path, or set NLSOFT_RIGS)");
  std::string where;
  for (const RigsFolder& f : folders) {
    const std::string path = f.dir + "/" + arg + ".toml";
    if (std::filesystem::is_regular_file(path)) {
      if (f.from_env) say_from_env(arg, path, f.dir, folders);
      return path;
    }
    where += (where.empty() ? "" : " and ") + f.dir;
  }
  throw CliError("unknown rig '" + printable(arg) + "'; rigs in " + where + ": " + joined(rig_names()) +
                 " (or give a rig file's path)");
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

}  // namespace nlsoft::host
