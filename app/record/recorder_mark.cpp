#include "app/record/recorder_mark.hpp"

#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>

namespace nlsoft::console {

namespace {

// kill(pid, 0) succeeds for a zombie too: a console killed with -9 whose
// parent has not reaped it yet is gone all the same.
bool process_running(int64_t pid) {
  if (pid <= 0) return false;
  if (::kill(pid_t(pid), 0) != 0 && errno != EPERM) return false;
  std::ifstream stat(fmt::format("/proc/{}/stat", pid));
  std::string text;
  if (!std::getline(stat, text)) return true;  // no /proc: kill's word stands
  const size_t paren = text.rfind(')');
  return paren == std::string::npos || paren + 2 >= text.size() || text[paren + 2] != 'Z';
}

std::string program_of(int64_t pid) {
  std::ifstream comm(fmt::format("/proc/{}/comm", pid));
  std::string name;
  std::getline(comm, name);
  return name.empty() ? "nlsoft-console" : name;
}

}  // namespace

std::string host_name() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "";
  return name;
}

double unix_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

MarkVerdict judge_mark(const RecorderMark& mark, double now) {
  MarkVerdict v;
  if (mark.pid <= 0) return v;
  const bool here = mark.host.empty() || mark.host == host_name();
  const bool running = here && process_running(mark.pid);
  v.holder = here ? fmt::format("{} (PID {})", running ? program_of(mark.pid) : "nlsoft-console", mark.pid)
                  : fmt::format("nlsoft-console (PID {} on {})", mark.pid, mark.host);
  const double age = now - mark.heartbeat_at;
  if (here && !running) {
    v.state = MarkVerdict::Stale;
    v.why = fmt::format("PID {} is no longer running (killed?)", mark.pid);
  } else if (age > kHeartbeatStaleS) {
    v.state = MarkVerdict::Stale;
    v.why = fmt::format("no heartbeat for {:.0f} s (its recorder is gone or frozen)", age);
  } else {
    v.state = MarkVerdict::Live;
  }
  return v;
}

}  // namespace nlsoft::console
