#include "host/paths/install_paths.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <filesystem>

// NLSOFT_BIN_TO_LIBEXEC and NLSOFT_BIN_TO_DATA: the install prefix's
// libexec/nlsoft and share/nlsoft relative to its bin, as GNUInstallDirs
// lays them out (cmake/layout.cmake), so a prefix works wherever it is put.

namespace nlsoft::host {

namespace {

// The build tree, relative to <build>/app where the console is built.
constexpr const char* kBuildFirmware = "../firmware";
constexpr const char* kBuildData = "../share/nlsoft";

bool executable(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), X_OK) == 0;
}

bool directory(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool readable(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(path.c_str(), R_OK) == 0;
}

// Tries each candidate once, in order, adding the misses to l.tried: the
// build tree and an install prefix can name the same file (models).
void first_of(Lookup& l, const std::vector<std::string>& candidates, bool (*ok)(const std::string&)) {
  for (const std::string& raw : candidates) {
    if (!l.found.empty()) return;
    // "/usr/bin/../share/..." reads as "/usr/share/..." in an error message.
    const std::string c = std::filesystem::path(raw).lexically_normal().string();
    bool seen = false;
    for (const std::string& t : l.tried) seen = seen || t == c;
    if (seen) continue;
    if (ok(c)) l.found = c;
    else l.tried.push_back(c);
  }
}

const char* env(const char* name) {
  const char* v = std::getenv(name);
  return v && *v ? v : nullptr;
}

}  // namespace

std::string Lookup::tried_lines() const {
  std::string s;
  for (const std::string& t : tried) s += "\n  " + t;
  return s;
}

std::string exe_dir() {
  char buf[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return {};
  const std::string p(buf, size_t(n));
  return p.substr(0, p.rfind('/'));
}

Lookup find_firmware_sim_file() {
  const std::string name = "nlsoft-firmware-sim", dir = exe_dir();
  Lookup l;
  if (const char* e = env("NLSOFT_FIRMWARE_SIM")) {
    if (executable(e)) return {e, {}};
    l.tried.push_back(std::string("$NLSOFT_FIRMWARE_SIM=") + e);
  }
  if (!dir.empty())
    first_of(l, {dir + "/" + kBuildFirmware + "/" + name, dir + "/" + name, dir + "/" NLSOFT_BIN_TO_LIBEXEC "/" + name},
             &executable);
  if (l.found.empty()) l.found = find_on_path(name);
  if (l.found.empty()) l.tried.push_back("PATH");
  return l;
}

Lookup find_image_file(const std::string& rel) {
  const std::string dir = exe_dir();
  Lookup l;
  if (!dir.empty())
    first_of(l, {dir + "/" + kBuildFirmware + "/" + rel, dir + "/" NLSOFT_BIN_TO_DATA "/firmware/" + rel}, &readable);
  return l;
}

Lookup find_model_file(const std::string& name) {
  const std::string dir = exe_dir();
  Lookup l;
  if (const char* e = env("NLSOFT_MODELS")) first_of(l, {std::string(e) + "/" + name}, &readable);
  // The last for the simulator, installed in libexec.
  if (!dir.empty())
    first_of(l, {dir + "/" + kBuildData + "/models/" + name, dir + "/" NLSOFT_BIN_TO_DATA "/models/" + name,
                 dir + "/" NLSOFT_LIBEXEC_TO_DATA "/models/" + name},
             &readable);
  return l;
}

Lookup find_rigs_dir() {
  const std::string dir = exe_dir();
  Lookup l;
  if (const char* e = env("NLSOFT_RIGS")) first_of(l, {e}, &directory);
  // The last for the simulator, installed in libexec and linking this too.
  if (!dir.empty())
    first_of(l, {dir + "/" + kBuildData + "/rigs", dir + "/" NLSOFT_BIN_TO_DATA "/rigs",
                 dir + "/" NLSOFT_LIBEXEC_TO_DATA "/rigs"},
             &directory);
  return l;
}

std::vector<RigsFolder> rigs_folders() {
  std::vector<RigsFolder> out;
  if (const char* e = env("NLSOFT_RIGS"); e && directory(e)) out.push_back({e, true});
  const std::string dir = exe_dir();
  Lookup l;
  if (!dir.empty())
    first_of(l, {dir + "/" + kBuildData + "/rigs", dir + "/" NLSOFT_BIN_TO_DATA "/rigs",
                 dir + "/" NLSOFT_LIBEXEC_TO_DATA "/rigs"},
             &directory);
  if (!l.found.empty()) out.push_back({l.found, false});
  return out;
}

Lookup find_firmware_src() {
  const std::string dir = exe_dir();
  Lookup l;
  bool (*const ok)(const std::string&) = [](const std::string& d) {
    return readable(d + "/firmware/ports/cortex-m/images.cmake") && readable(d + "/cmake/warning_flags.txt");
  };
  if (const char* e = env("NLSOFT_FIRMWARE_SRC")) first_of(l, {e}, ok);
  if (!dir.empty())
    first_of(l, {dir + "/" + kBuildData + "/firmware-src", dir + "/" NLSOFT_BIN_TO_DATA "/firmware-src"}, ok);
  return l;
}

std::string find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  const std::string all = path;
  size_t pos = 0;
  while (pos <= all.size()) {
    const size_t colon = all.find(':', pos);
    const std::string d = all.substr(pos, colon == std::string::npos ? std::string::npos : colon - pos);
    pos = colon == std::string::npos ? all.size() + 1 : colon + 1;
    if (!d.empty() && executable(d + "/" + name)) return d + "/" + name;
  }
  return {};
}

}  // namespace nlsoft::host
