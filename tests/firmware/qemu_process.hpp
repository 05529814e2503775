#pragma once
// Test support: boots a Cortex-M4F image in qemu-system-arm with the link's
// UART on a pseudo-terminal and reads the pty path QEMU reports; kills QEMU
// when the test ends. Boards: mps2-an386 (UART0, the first serial port) and
// stm32f4 (USART2 of -M netduinoplus2, the second). `extra`: more QEMU
// arguments (chip models as -device, a -qmp socket).
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>
#include <vector>

namespace nlsoft::test {

inline bool qemu_arm_available() {
  return std::system("command -v qemu-system-arm >/dev/null 2>&1") == 0;
}

class QemuProcess {
 public:
  explicit QemuProcess(const std::string& elf, const std::string& board = "mps2-an386",
                       const std::vector<std::string>& extra = {}) {
    std::vector<const char*> argv = {"qemu-system-arm", "-nographic", "-monitor", "none", "-icount", "shift=0"};
    if (board == "stm32f4")
      argv.insert(argv.end(), {"-M", "netduinoplus2", "-serial", "null", "-serial", "pty"});
    else
      argv.insert(argv.end(), {"-M", "mps2-an386", "-serial", "pty"});
    for (const std::string& a : extra) argv.push_back(a.c_str());
    argv.insert(argv.end(), {"-kernel", elf.c_str(), nullptr});
    int out[2];
    if (pipe(out) != 0) return;
    pid_ = fork();
    if (pid_ == 0) {
      dup2(out[1], STDOUT_FILENO);
      dup2(out[1], STDERR_FILENO);
      close(out[0]);
      close(out[1]);
      execvp(argv[0], const_cast<char* const*>(argv.data()));
      _exit(127);
    }
    close(out[1]);
    out_ = out[0];
    // "char device redirected to /dev/pts/N (label serial0)"
    std::string line;
    char c;
    while (read(out_, &c, 1) == 1) {
      if (c != '\n') {
        line += c;
        continue;
      }
      const auto at = line.find("redirected to ");
      if (at != std::string::npos) {
        const auto start = at + 14;
        path_ = line.substr(start, line.find(' ', start) - start);
        break;
      }
      log_ += line + "\n";
      line.clear();
    }
  }
  ~QemuProcess() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      int st;
      waitpid(pid_, &st, 0);
    }
    if (out_ >= 0) close(out_);  // kept open until now: QEMU may still write to it
  }
  const std::string& path() const { return path_; }
  // What QEMU printed before the pty line (its error when there is none).
  const std::string& log() const { return log_; }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  std::string path_, log_;
};

}  // namespace nlsoft::test
