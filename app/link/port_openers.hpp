#pragma once
// Who else has a serial device open. flock and TIOCEXCL keep out consoles
// and programs that open the port after this one; a program that opened it
// before (`cat /dev/pts/5 &`, a forgotten `screen`) is only found by looking
// at every process's open files: /proc/PID/fd links that lead to the same
// device. No library lists a device's openers (lsof and fuser are programs
// doing the same walk), so it is written here.
#include <string>
#include <sys/stat.h>
#include <sys/types.h>
#include <vector>

namespace nlsoft::console {

struct PortOpener {
  pid_t pid = 0;
  std::string command;  // /proc/PID/comm
};

// Processes other than this one with the device behind fd open, in PID
// order. Left out: on a pseudo-terminal, the process holding its master
// side (the firmware simulator or QEMU: the other end of the line, which
// also keeps the slave open so the line survives between consoles).
// Processes of other users whose /proc/PID/fd this one may not read are not
// seen.
std::vector<PortOpener> other_openers(int fd);
std::vector<PortOpener> other_openers(const std::string& path);  // by name, without opening it
std::vector<PortOpener> other_openers(const struct stat& device);

// "PID 1234 (cat)", "PID 1234 (cat) and PID 99 (screen)".
std::string describe_openers(const std::vector<PortOpener>& openers);
// "PID 1234 (cat) also has PORT open": the one phrase every "no reply" uses.
std::string also_open_words(const std::vector<PortOpener>& openers, const std::string& port);

}  // namespace nlsoft::console
