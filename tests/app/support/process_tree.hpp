#pragma once
// Processes as a person handles them from a shell: a command started in the
// background (`sh -c`), and a process found under another, as with pstree
// or ps (the simulator a console started, to kill it as a user would).
#include <sys/types.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace nlsoft::test {

// Starts `command` under /bin/sh in a child process; its PID, or -1.
inline pid_t start_shell(const std::string& command) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

// A process under `root` whose name (comm, at most 15 characters) starts
// `name`; 0 if none.
inline pid_t descendant_named(pid_t root, const std::string& name) {
  for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
    const std::string dir = entry.path().filename().string();
    if (dir.empty() || dir.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream comm(entry.path() / "comm");
    std::string c;
    std::getline(comm, c);
    if (c.empty() || c.rfind(name.substr(0, 15), 0) != 0) continue;
    for (pid_t p = pid_t(std::stoi(dir)); p > 1;) {
      std::ifstream stat("/proc/" + std::to_string(p) + "/stat");
      std::string text;
      std::getline(stat, text);
      const size_t paren = text.rfind(')');
      if (paren == std::string::npos || paren + 2 >= text.size()) break;
      std::istringstream rest(text.substr(paren + 2));
      char state = 0;
      int ppid = 0;
      rest >> state >> ppid;
      if (ppid == root) return pid_t(std::stoi(dir));
      p = ppid;
    }
  }
  return 0;
}

}  // namespace nlsoft::test
