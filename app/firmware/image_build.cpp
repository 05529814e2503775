#include "app/firmware/image_build.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <functional>
#include <sstream>
#include <string_view>
#include <thread>
#include <vector>

#include "host/files/cli_error.hpp"
#include "app/firmware/generated_text.hpp"
#include "app/firmware/image_header.hpp"
#include "host/paths/install_paths.hpp"
#include "host/files/printable.hpp"
#include "app/progress_bar.hpp"
#include "host/rig/board_table.hpp"
#include "host/rig/rig_catalog.hpp"
#include "shared/crc32.hpp"

namespace nlsoft::console {

using host::Board;
using host::CliError;
using host::Lookup;
using host::Rig;
using host::RigError;
using host::RigsFolder;
using host::board_for;
using host::find_firmware_src;
using host::find_image_file;
using host::find_model_file;
using host::find_on_path;
using host::image_file_name;
using host::load_rig;
using host::printable;
using host::rigs_folders;
using host::shipped_image;

namespace fs = std::filesystem;

namespace {

constexpr const char* kToolchainPackages = "gcc-arm-none-eabi libnewlib-arm-none-eabi cmake";


std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Set by SIGINT while the build tools run (interruptible below).
volatile std::sig_atomic_t g_interrupted = 0;
extern "C" void on_interrupt(int) { g_interrupted = 1; }

// Ctrl-C while the images build: the tools, in a process group of their
// own, are stopped by the console, which then says what is left (the
// images of the folder as they were) instead of dying silently.
class Interruptible {
 public:
  Interruptible() {
    g_interrupted = 0;
    struct sigaction sa {};
    sa.sa_handler = on_interrupt;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = 0;  // no SA_RESTART: the read of the tools' output returns EINTR
    ::sigaction(SIGINT, &sa, &old_int_);
    ::sigaction(SIGTERM, &sa, &old_term_);
  }
  ~Interruptible() {
    ::sigaction(SIGINT, &old_int_, nullptr);
    ::sigaction(SIGTERM, &old_term_, nullptr);
    g_interrupted = 0;
  }
  Interruptible(const Interruptible&) = delete;
  Interruptible& operator=(const Interruptible&) = delete;

 private:
  struct sigaction old_int_ {}, old_term_ {};
};

// Runs argv (no shell: its words are data) in a process group of its own,
// handing each piece of its stdout and stderr to on_output; returns the
// exit status. An interrupt (g_interrupted) is passed on to the group.
int run_piped(const std::vector<std::string>& argv_in, const std::function<void(const char*, size_t)>& on_output) {
  int out[2];
  if (::pipe2(out, O_CLOEXEC) != 0) throw CliError(fmt::format("pipe: {}", std::strerror(errno)));
  std::vector<std::string> args = argv_in;
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) throw CliError(fmt::format("fork: {}", std::strerror(errno)));
  if (pid == 0) {
    ::setpgid(0, 0);
    ::signal(SIGINT, SIG_DFL);
    ::signal(SIGTERM, SIG_DFL);
    ::dup2(out[1], STDOUT_FILENO);
    ::dup2(out[1], STDERR_FILENO);
    ::execvp(argv[0], argv.data());
    std::fprintf(stderr, "cannot run %s: %s\n", argv[0], std::strerror(errno));
    ::_exit(127);
  }
  ::setpgid(pid, pid);  // also here: a signal may come before the child ran setpgid
  ::close(out[1]);
  bool passed_on = false;
  char buf[4096];
  for (;;) {
    if (g_interrupted && !passed_on) ::kill(-pid, SIGINT), passed_on = true;
    const ssize_t n = ::read(out[0], buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    on_output(buf, size_t(n));
  }
  ::close(out[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    if (g_interrupted && !passed_on) ::kill(-pid, SIGINT), passed_on = true;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// run_piped with the output appended to `log`, line by line to on_line.
// The build tools' output is only shown when they fail.
int run_logged(const std::vector<std::string>& argv, const std::string& log,
               const std::function<void(const std::string&)>& on_line) {
  std::ofstream logf(log, std::ios::app);
  std::string pending;
  return run_piped(argv, [&](const char* data, size_t n) {
    logf.write(data, std::streamsize(n));
    pending.append(data, n);
    for (size_t nl; (nl = pending.find('\n')) != std::string::npos; pending.erase(0, nl + 1))
      on_line(pending.substr(0, nl));
  });
}

// "[ 42%] Building ..." as make prints it.
int make_percent(const std::string& line) {
  if (line.size() < 6 || line[0] != '[' || line[4] != '%') return -1;
  return std::atoi(line.c_str() + 1);
}

// What make's line says it does, in a few words: "compiling main.cpp",
// "linking nlsoft-stm32f4-arm.elf", "" for anything else.
std::string make_step(const std::string& line) {
  const size_t last = line.find_last_of(" /");
  const std::string name = last == std::string::npos ? line : line.substr(last + 1);
  if (line.find("] Building ") != std::string::npos) return "compiling " + name.substr(0, name.rfind(".o"));
  if (line.find("] Linking ") != std::string::npos) return "linking " + name;
  return "";
}

void require_toolchain(const std::string& who) {
  std::string missing;
  for (const char* tool : {"arm-none-eabi-g++", "arm-none-eabi-size", "cmake"})
    if (find_on_path(tool).empty()) missing += std::string(missing.empty() ? "" : ", ") + tool;
  // newlib: the C library the images link (nano.specs); the compiler alone lacks it.
  if (missing.empty()) {
    std::string found;
    if (FILE* p = ::popen("arm-none-eabi-g++ -print-file-name=libc_nano.a 2>/dev/null", "r")) {
      char line[4096];
      if (std::fgets(line, sizeof line, p)) found = line;
      ::pclose(p);
    }
    while (!found.empty() && (found.back() == '\n' || found.back() == '\r')) found.pop_back();
    if (found.find('/') == std::string::npos || !fs::exists(found)) missing = "newlib for arm-none-eabi";
  }
  if (!missing.empty())
    throw CliError(fmt::format("{}: building an image needs the Cortex-M toolchain; not found: {}. Install it: "
                               "apt-get install {}",
                               who, missing, kToolchainPackages));
}

std::string firmware_src(const std::string& who) {
  const Lookup l = find_firmware_src();
  if (!l.found.empty()) return l.found;
  throw CliError(fmt::format("{}: cannot find the firmware sources; tried:{}\nset NLSOFT_FIRMWARE_SRC to an nlsoft "
                             "source tree",
                             who, l.tried_lines()));
}

// The XDG rules, as for the recording database: $XDG_CACHE_HOME when it is
// an absolute path (a relative one is ignored), else $HOME/.cache. HOME must
// be there: HOME=/nonexistent made /nonexistent/.cache/... at the root, and a
// relative HOME a folder wherever the console ran. XDG_CACHE_HOME may be
// made, as the XDG rules ask, but only inside a folder that is there (one
// level, never a chain of folders from a mistyped path).
std::string cache_dir() {
  const std::string fix = "set XDG_CACHE_HOME or HOME to a folder, or give --out";
  auto existing = [&](const char* var, const std::string& value) {
    struct stat st {};
    const bool there = ::stat(value.c_str(), &st) == 0;
    if (!there || !S_ISDIR(st.st_mode))
      throw CliError(fmt::format("no folder for the image cache: {}={} {}; {}", var, printable(value),
                                 there ? "is not a folder" : "does not exist", fix));
    return value;
  };
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg == '/') {
    std::string dir = xdg;
    while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
    const std::string parent = dir.substr(0, std::max<size_t>(1, dir.rfind('/')));
    struct stat st {};
    if (::stat(dir.c_str(), &st) != 0 && ::stat(parent.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
      ::mkdir(dir.c_str(), 0700);  // fails only if it appeared meanwhile or cannot be made: `existing` says which
    return existing("XDG_CACHE_HOME", dir) + "/nlsoft/firmware";
  }
  const char* home = std::getenv("HOME");
  if (!home || !*home) throw CliError("no folder for the image cache: HOME is not set; " + fix);
  if (*home != '/')
    throw CliError(fmt::format("no folder for the image cache: HOME={} is not an absolute path; {}", printable(home),
                               fix));
  return existing("HOME", home) + "/.cache/nlsoft/firmware";
}

// The cache folder of an image: keyed by the header, which says everything
// about the rig and the board, and the bytes of the model embedded.
std::string cache_folder(const Rig& rig, const std::string& board, const ImageSource& source,
                         const std::string& model_file) {
  std::string keyed = source.header + source.cmake;
  if (!model_file.empty()) keyed += read_file(model_file);
  const uint32_t key = crc32(reinterpret_cast<const uint8_t*>(keyed.data()), keyed.size());
  return fmt::format("{}/{}-{}-{:08x}", cache_dir(), rig.name, board, key);
}

// The image (the HIL one, or the board's) `firmware build --rig FILE --model M`
// made last from this very file for `board`: a cache folder of the rig whose key is still the
// one the file and its model M give now (neither changed since), with the
// newest such image. Found by reading each folder's image.cmake for M.
struct LastBuilt {
  std::string dir, model;
};
LastBuilt last_built_with_model(const Rig& rig, const std::string& board, bool hil) {
  LastBuilt best;
  std::error_code ec;
  std::string cache;
  try {
    cache = cache_dir();
  } catch (const CliError&) {
    return best;
  }
  fs::file_time_type newest{};
  const std::string prefix = rig.name + "-" + board + "-";
  for (const auto& e : fs::directory_iterator(cache, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind(prefix, 0) != 0 || name.size() != prefix.size() + 8) continue;
    const std::string cmake = read_file(e.path().string() + "/.rig/" + rig.name + "/image.cmake");
    // The model the user named (the image embeds a copy of it).
    const std::string model =
        cmake_bracket_value(cmake, "NLSOFT_IMAGE_MODEL_SOURCE").value_or(std::string());
    const std::string elf = e.path().string() + "/" + image_file_name(board_for(board, "--board"), rig.name, hil);
    if (model.empty() || !fs::exists(model, ec) || !fs::exists(elf, ec)) continue;
    // A HIL image comes from a build of both images or of the HIL one alone (--hil), each its own folder.
    bool current = false;
    for (ImageKinds kinds : {ImageKinds::Both, ImageKinds::Hil}) {
      if (kinds == ImageKinds::Hil && !hil) continue;
      try {
        ImageRequest request;
        request.board = board;
        request.images = kinds;
        request.model_file = model;
        current = current || cache_folder(rig, board, image_source(rig, request), model) == e.path().string();
      } catch (const std::exception&) {
        // a model that no longer fits the rig, or a board that runs only the HIL image
      }
    }
    if (!current) continue;
    const fs::file_time_type t = fs::last_write_time(elf, ec);
    if (!ec && (best.dir.empty() || t > newest)) best = {e.path().string(), model}, newest = t;
  }
  return best;
}

BuiltImage sized(const std::string& path) {
  BuiltImage b;
  b.path = path;
  std::string text;
  run_piped({"arm-none-eabi-size", path}, [&](const char* data, size_t n) { text.append(data, n); });
  std::istringstream in(text);
  long text_bytes = 0, data = 0, bss = 0;
  for (std::string line; std::getline(in, line);)
    if (std::sscanf(line.c_str(), "%ld %ld %ld", &text_bytes, &data, &bss) == 3)
      b.flash = text_bytes + data, b.ram = data + bss;
  return b;
}

// The build tools take the image folder's path into CMake code, makefiles,
// compiler options and an assembler string; in these it stays a path only
// without the characters each of them treats as syntax.
void check_image_folder(const std::string& dir, const std::string& option, const std::string& who) {
  constexpr std::string_view kSyntax = "\"'\\$;#`";
  for (const char c : dir) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f || kSyntax.find(c) != std::string_view::npos)
      throw CliError(fmt::format("{}: {} '{}': the build tools take an image folder without control characters and "
                                 "without any of {}; choose another folder",
                                 who, option, printable(dir), kSyntax));
  }
}

// The folder's images replaced by the ones just built in `staged`, each
// copied beside its final name and renamed over it: a reader (or an
// interrupted build) never sees half an image. One the build left as it
// was is left alone, time stamp and all.
void publish_images(const std::string& staged, const std::string& dir, const std::string& who) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(staged, ec)) {
    if (!e.is_regular_file()) continue;
    const std::string name = e.path().filename().string();
    const std::string tmp = dir + "/." + name + ".tmp", final_path = dir + "/" + name;
    std::error_code size_ec;
    if (fs::file_size(final_path, size_ec) == e.file_size() && !size_ec &&
        read_file(final_path) == read_file(e.path().string()))
      continue;
    fs::copy_file(e.path(), tmp, fs::copy_options::overwrite_existing, ec);
    if (!ec) fs::rename(tmp, final_path, ec);
    if (ec) {
      fs::remove(tmp);
      throw CliError(fmt::format("{}: cannot write {}: {}", who, final_path, ec.message()));
    }
  }
  if (ec) throw CliError(fmt::format("{}: cannot read {}: {}", who, staged, ec.message()));
}

// The last lines of a failed build that say why.
std::string build_failure(const std::string& log, const Rig& rig, const std::string& board, const std::string& who) {
  const std::string text = read_file(log);
  // The linker's words for a region too small, and sections.ld's for no stack left.
  if (text.find("overflowed") != std::string::npos || text.find("will not fit in region") != std::string::npos ||
      text.find("leaves no room for the stack") != std::string::npos)
  {
    // The linker's own line ("region `FLASH' overflowed by 3412 bytes"), and
    // what a rig file can leave out to fit a small part.
    std::string said;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
      if (const size_t at = line.find("region "); at != std::string::npos && line.find("overflowed") != std::string::npos) {
        said = ": " + line.substr(at);
        break;
      }
    return fmt::format("{}: rig '{}' ({}) does not fit board {}'s memory (m = {}, n = {}, w = {}, N = {}, Nc = {}){}; "
                       "a rig file's [firmware] table leaves services out (features = []) and builds for size "
                       "(optimize = \"size\"), docs/rig-file.md; the linker's log: {}",
                       who, rig.name, rig.file, board, rig.m(), rig.n(), rig.w(), rig.controller.N, rig.controller.Nc,
                       said, log);
  }
  std::vector<std::string> errors;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.find("error") != std::string::npos) errors.push_back(line);
  std::string shown;
  for (size_t i = errors.size() > 5 ? errors.size() - 5 : 0; i < errors.size(); ++i) shown += "\n  " + errors[i];
  return fmt::format("{}: the image build for rig '{}' on {} failed (log: {}){}", who, rig.name, board, log, shown);
}

// A shipped rig's name when `rig` is one of the shipped files as shipped.
std::string shipped_name(const Rig& rig) {
  // The shipped folder's, not $NLSOFT_RIGS's: its prebuilt images are of
  // the shipped files.
  std::string shipped;
  for (const RigsFolder& f : rigs_folders())
    if (!f.from_env) shipped = f.dir;
  if (shipped.empty()) return "";
  const std::string file = shipped + "/" + rig.name + ".toml";
  if (!fs::exists(file)) return "";
  // The shipped file itself needs no second read.
  std::error_code ec;
  if (fs::equivalent(file, rig.file, ec)) return rig.name;
  try {
    return load_rig(file).hash == rig.hash ? rig.name : "";
  } catch (const std::exception&) {
    return "";
  }
}

// The model file the images embed, absolute (the cache folder is keyed by
// this name and --qemu finds the image by it, last_built_with_model, from
// whatever folder it is run in): --model, else the rig's [model] among the
// shipped models, else none and `note` says so.
std::string model_for_image(const Rig& rig, const ImageBuild& q, std::string& note) {
  if (!q.model.empty()) return fs::absolute(q.model).lexically_normal().string();
  if (rig.model.file.empty()) return "";
  if (const std::string found = find_model_file(rig.model.file).found; !found.empty())
    return fs::absolute(found).lexically_normal().string();
  note = fmt::format("no model embedded: {} is not among the shipped models; the image waits for an upload "
                     "(or give --model)",
                     rig.model.file);
  return "";
}

// An image folder's parts. The images are linked in .build/images and
// copied out once all are built: an interrupted or failed build leaves the
// folder's images as they were, and no part of a new one beside them. What
// the build is made from (the rig folder, the model's copy) is staged in
// .build too and recorded in .rig and model.nlsm only with the images: a
// Ctrl-C left them naming the new model beside the old images.
struct ImageFolder {
  explicit ImageFolder(const std::string& d)
      : dir(d), rigs(d + "/.rig"), build(d + "/.build"), staged(build + "/images"), staged_rigs(build + "/rig"),
        staged_model(build + "/model"), log(d + "/build.log") {}
  std::string dir, rigs, build, staged, staged_rigs, staged_model, log;
};

// The rig folder and the model's copy staged for the port project, one rig
// per folder (the port project builds every rig folder it finds). The
// image embeds a copy of the model in its folder, so the build tools never
// take the path the user gave; the model alone: what a file carries after
// it (train's fit) is not the firmware's, and its boot parse would refuse it.
void stage_sources(const Rig& rig, const ImageFolder& f, ImageRequest& request, ImageSource& source,
                   const std::string& who) {
  std::error_code ec;
  for (const std::string& d : {f.rigs, f.staged_rigs}) {
    fs::create_directories(d, ec);
    if (ec) throw CliError(fmt::format("{}: cannot create {}: {}", who, d, ec.message()));
    for (const auto& e : fs::directory_iterator(d))
      if (e.path().filename() != rig.name) fs::remove_all(e.path(), ec);
  }
  // The model's copy is rewritten only when its bytes changed: a new mtime
  // reassembles the model blob and relinks every image (LTO), 6 s of a
  // --qemu connect that changed nothing.
  if (request.model_file.empty()) fs::remove_all(f.staged_model, ec);
  else {
    const std::string given = request.model_file;
    request.model_file = model_copy_for_image(given, f.staged_model);
    source = image_source(rig, request);
    // The file the user named, so --qemu FILE finds this image by it
    // (last_built_with_model): the folder is keyed by that file.
    source.cmake += fmt::format("set(NLSOFT_IMAGE_MODEL_SOURCE {})\n", cmake_bracket(given));
  }
  write_image_source(source, f.staged_rigs + "/" + rig.name);
  fs::remove(f.log, ec);
}

// The port project configured and built into .build (a progress bar from
// make's percentages), a Ctrl-C meanwhile leaving the folder as it was.
void compile_images(const Rig& rig, const ImageBuild& q, const ImageFolder& f, const std::string& src,
                    const std::string& what) {
  auto interrupted = [&] {
    if (g_interrupted)
      throw CliError(fmt::format("{}: interrupted: the images in {} are the ones it held before", q.who, f.dir), 130);
  };
  ProgressBar bar("building " + what);
  auto progress = [&](const std::string& line) {
    if (const int p = make_percent(line); p >= 0) bar.update(p, 100, make_step(line));
  };
  bar.update(0, 100, "configuring (cmake)");
  const int configured = run_logged(
      {"cmake", "-S", src + "/firmware/ports/" + q.board, "-B", f.build,
       "-DCMAKE_TOOLCHAIN_FILE=" + src + "/firmware/ports/cortex-m/cmake/arm-none-eabi.cmake", "-DNLSOFT_ROOT=" + src,
       "-DNLSOFT_RIG_DIR=" + f.staged_rigs, std::string("-DNLSOFT_IMAGE_KINDS=") + (q.hil_only ? "hil" : "both"),
       "-DCMAKE_RUNTIME_OUTPUT_DIRECTORY=" + f.staged},
      f.log, [](const std::string&) {});
  interrupted();
  if (configured != 0) throw CliError(build_failure(f.log, rig, q.board, q.who));
  const unsigned cores = std::thread::hardware_concurrency();
  const int built =
      run_logged({"cmake", "--build", f.build, "-j", std::to_string(cores > 0 ? cores : 1)}, f.log, progress);
  interrupted();
  if (built != 0) throw CliError(build_failure(f.log, rig, q.board, q.who));
}

// The built images into the folder, then what they were built from: the rig
// folder, and the model's copy (none now: an older build's copy would name
// another model). Not interrupted half way: SIGINT waits until every image
// is in place.
void publish_build(const Rig& rig, const ImageFolder& f, bool with_model, const std::string& who) {
  sigset_t block, old;
  sigemptyset(&block);
  sigaddset(&block, SIGINT);
  sigaddset(&block, SIGTERM);
  ::pthread_sigmask(SIG_BLOCK, &block, &old);
  try {
    std::error_code ec;
    publish_images(f.staged, f.dir, who);
    fs::create_directories(f.rigs + "/" + rig.name, ec);
    publish_images(f.staged_rigs + "/" + rig.name, f.rigs + "/" + rig.name, who);
    if (!with_model) fs::remove(f.dir + "/model.nlsm", ec);
    else publish_images(f.staged_model, f.dir, who);
  } catch (...) {
    ::pthread_sigmask(SIG_SETMASK, &old, nullptr);
    throw;
  }
  ::pthread_sigmask(SIG_SETMASK, &old, nullptr);  // a Ctrl-C meanwhile came after the build: it is done
}

}  // namespace

BuiltImages build_images(const Rig& rig, const ImageBuild& q) {
  if (q.hil_only && rig.plant.kind == nullptr)
    throw CliError(fmt::format("{}: rig '{}' ({}) has no [plant]: there is no HIL image to build, only the board's "
                               "(without --hil)",
                               q.who, rig.name, rig.file));
  ImageRequest request;
  request.board = q.board;
  request.images = q.hil_only ? ImageKinds::Hil : ImageKinds::Both;
  std::string note;
  request.model_file = model_for_image(rig, q, note);
  ImageSource source;
  try {
    source = image_source(rig, request);
  } catch (const RigError& e) {
    throw CliError(fmt::format("{}: {}", q.who, e.what()));
  } catch (const CliError& e) {
    throw CliError(fmt::format("{}: {}", q.who, e.what()), e.exit_code);
  }
  require_toolchain(q.who);
  const std::string src = firmware_src(q.who);

  const ImageFolder f(!q.out.empty() ? fs::absolute(q.out).lexically_normal().string()
                                     : cache_folder(rig, q.board, source, request.model_file));
  check_image_folder(f.dir, q.out.empty() ? "the cache folder" : "--out", q.who);
  stage_sources(rig, f, request, source, q.who);

  const Board& board = board_for(q.board, "--board");
  const std::string what = fmt::format("{}-{}{}", board.image_prefix, rig.name, q.hil_only ? "-hil" : "");
  const bool tty = ::isatty(STDERR_FILENO) != 0;
  if (!note.empty()) std::fprintf(stderr, "%s: %s\n", q.who.c_str(), note.c_str());
  if (!source.note.empty()) std::fprintf(stderr, "%s: %s\n", q.who.c_str(), source.note.c_str());
  if (!tty) std::fprintf(stderr, "%s: building %s for %s in %s\n", q.who.c_str(), what.c_str(), q.board.c_str(), f.dir.c_str());
  {
    const Interruptible interruptible;
    compile_images(rig, q, f, src, what);
    publish_build(rig, f, !request.model_file.empty(), q.who);
  }
  BuiltImages out;
  out.dir = f.dir;
  const std::string board_elf = f.dir + "/" + image_file_name(board, rig.name, false);
  const std::string hil_elf = f.dir + "/" + image_file_name(board, rig.name, true);
  if (!q.hil_only && fs::exists(board_elf)) out.board = sized(board_elf);
  if (source.hil && fs::exists(hil_elf)) out.hil = sized(hil_elf);
  if (out.board.path.empty() && out.hil.path.empty())
    throw CliError(fmt::format("{}: the build made no image (log: {})", q.who, f.log));
  return out;
}

std::string hil_image_for(const Rig& rig, const std::string& board, const std::string& who,
                          const std::string& model) {
  if (const char* env = std::getenv("NLSOFT_M4_IMAGE"); env && *env) {
    if (::access(env, R_OK) == 0) return env;
    throw CliError(fmt::format("$NLSOFT_M4_IMAGE={} cannot be read", env));
  }
  if (rig.plant.kind == nullptr)
    throw CliError(fmt::format("{}: rig '{}' ({}) has no [plant]: QEMU runs an image with the simulated plant in the "
                               "loop; `firmware build --rig {}` builds its board image",
                               who, rig.name, rig.file, rig.file));
  if (const std::string shipped = shipped_name(rig); !shipped.empty()) {
    if (const Lookup l = find_image_file(shipped_image(board_for(board, "--board"), shipped, true)); !l.found.empty())
      return l.found;
  }
  ImageBuild q;
  q.board = board;
  q.model = model;
  // The cache folder `firmware build` fills: both images, built once; on a
  // board the rig's chips are not on, the HIL image alone (`firmware build
  // --hil`), as the board can run no other (image_header.hpp, ImageKinds).
  const bool chips_elsewhere = !rig.devices.empty() && rig.board != board;
  q.hil_only = chips_elsewhere;
  q.who = who;
  if (q.model.empty()) {
    // The image last built from this file with a model (`firmware build
    // --model`), as built: only its HIL image when that is all it has.
    const LastBuilt last = last_built_with_model(rig, board, true);
    q.model = last.model;
    const std::string board_elf = image_file_name(board_for(board, "--board"), rig.name, false);
    q.hil_only = chips_elsewhere || (!last.dir.empty() && !fs::exists(last.dir + "/" + board_elf));
  }
  return build_images(rig, q).hil.path;
}

std::string image_for(const Rig& rig, const std::string& board, bool hil, const std::string& who) {
  if (const std::string shipped = shipped_name(rig); !shipped.empty()) {
    if (const Lookup l = find_image_file(shipped_image(board_for(board, "--board"), shipped, hil)); !l.found.empty())
      return l.found;
  }
  ImageBuild q;
  q.board = board;
  q.model = last_built_with_model(rig, q.board, hil).model;
  q.who = who;
  const BuiltImages b = build_images(rig, q);
  const std::string path = hil ? b.hil.path : b.board.path;
  if (path.empty())
    throw CliError(fmt::format("{}: rig '{}' ({}) has no [plant]: no HIL image", who, rig.name, rig.file));
  return path;
}

}  // namespace nlsoft::console
