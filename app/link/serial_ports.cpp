#include "app/link/serial_ports.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>

namespace nlsoft::console {

namespace fs = std::filesystem;

namespace {

std::string first_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line;
}

// sysfs: /sys/dev/char/MAJ:MIN is the tty's folder; the USB device that
// carries it is the first folder above with an idVendor (the interface's
// parent for ttyACM, one more up for ttyUSB).
void read_usb_facts(const PortRoots& roots, SerialPort& p) {
  struct stat st {};
  if (::stat(p.device.c_str(), &st) != 0 || !S_ISCHR(st.st_mode)) return;
  std::error_code ec;
  const fs::path root = fs::weakly_canonical(roots.sysfs, ec);
  fs::path dir = fs::canonical(fs::path(roots.sysfs) / "dev" / "char" /
                                   fmt::format("{}:{}", major(st.st_rdev), minor(st.st_rdev)),
                               ec);
  if (ec) return;
  for (int up = 0; up < 8 && dir.has_relative_path() && dir != root; ++up, dir = dir.parent_path()) {
    const std::string vendor = first_line(dir / "idVendor");
    if (vendor.empty()) continue;
    p.usb_id = vendor + ":" + first_line(dir / "idProduct");
    std::transform(p.usb_id.begin(), p.usb_id.end(), p.usb_id.begin(), [](unsigned char c) { return std::tolower(c); });
    p.manufacturer = first_line(dir / "manufacturer");
    p.product = first_line(dir / "product");
    p.serial = first_line(dir / "serial");
    return;
  }
}

// Every process's open files, matched by device number: the port may have
// been opened by any of its names (by-id, /dev/ttyACM0). Processes of
// other users cannot be looked into without privileges; they stay unseen.
std::vector<std::vector<PortHolder>> find_holders(const std::vector<SerialPort>& ports) {
  std::vector<std::vector<PortHolder>> out(ports.size());
  std::vector<dev_t> rdev(ports.size(), 0);
  for (size_t i = 0; i < ports.size(); ++i) {
    struct stat st {};
    if (::stat(ports[i].device.c_str(), &st) == 0 && S_ISCHR(st.st_mode)) rdev[i] = st.st_rdev;
  }
  const std::string self = std::to_string(::getpid());
  std::error_code ec;
  for (const auto& proc : fs::directory_iterator("/proc", ec)) {
    const std::string pid = proc.path().filename().string();
    if (pid.empty() || pid.find_first_not_of("0123456789") != std::string::npos || pid == self) continue;
    std::set<size_t> held;
    std::error_code e2;
    for (const auto& fd : fs::directory_iterator(proc.path() / "fd", e2)) {
      struct stat st {};
      if (::stat(fd.path().c_str(), &st) != 0 || !S_ISCHR(st.st_mode)) continue;
      for (size_t i = 0; i < ports.size(); ++i)
        if (rdev[i] != 0 && st.st_rdev == rdev[i]) held.insert(i);
    }
    if (held.empty()) continue;
    // The command line's arguments are NUL-separated.
    std::ifstream in(proc.path() / "cmdline", std::ios::binary);
    std::string cmd((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    while (!cmd.empty() && cmd.back() == '\0') cmd.pop_back();
    std::replace(cmd.begin(), cmd.end(), '\0', ' ');
    if (cmd.empty()) cmd = first_line(proc.path() / "comm");
    for (size_t i : held) out[i].push_back({std::atoi(pid.c_str()), cmd});
  }
  for (auto& h : out) std::sort(h.begin(), h.end(), [](const PortHolder& a, const PortHolder& b) { return a.pid < b.pid; });
  return out;
}

}  // namespace

PortRoots PortRoots::from_environment() {
  PortRoots r;
  if (const char* v = std::getenv("NLSOFT_SERIAL_BY_ID"); v && *v) r.by_id = v;
  if (const char* v = std::getenv("NLSOFT_SYSFS"); v && *v) r.sysfs = v;
  return r;
}

std::string board_of_usb_id(const std::string& usb_id) {
  // ST-LINK/V2, V2-1 (Nucleo-64's on-board probe), V3 variants.
  static const char* const kStLink[] = {"0483:3744", "0483:3748", "0483:374a", "0483:374b", "0483:374d",
                                        "0483:374e", "0483:374f", "0483:3752", "0483:3753", "0483:3754"};
  // Teensy in its USB types that carry a serial port (Serial, Serial + ...,
  // dual and triple serial).
  static const char* const kTeensy[] = {"16c0:0483", "16c0:0487", "16c0:0489", "16c0:048a", "16c0:048b",
                                        "16c0:048c", "16c0:0476"};
  for (const char* id : kStLink)
    if (usb_id == id) return "ST-LINK";
  for (const char* id : kTeensy)
    if (usb_id == id) return "Teensy";
  return "";
}

std::vector<SerialPort> list_serial_ports(const PortRoots& roots) {
  std::vector<SerialPort> ports;
  std::set<std::string> devices;
  std::error_code ec;
  std::vector<fs::path> links;
  for (const auto& e : fs::directory_iterator(roots.by_id, ec)) links.push_back(e.path());
  std::sort(links.begin(), links.end());
  for (const fs::path& link : links) {
    std::error_code e2;
    const fs::path device = fs::canonical(link, e2);
    if (e2) continue;  // a dangling link: the device is gone
    SerialPort p;
    p.path = link.string();
    p.device = device.string();
    devices.insert(p.device);
    ports.push_back(p);
  }
  // USB ttys udev gave no by-id name (no serial number, no udev at all).
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(fs::path(roots.sysfs) / "class" / "tty", ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("ttyACM", 0) == 0 || name.rfind("ttyUSB", 0) == 0) names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  for (const std::string& name : names) {
    const std::string dev = "/dev/" + name;
    std::error_code e2;
    if (!fs::exists(dev, e2) || devices.count(fs::canonical(dev, e2).string())) continue;
    SerialPort p;
    p.path = p.device = dev;
    ports.push_back(p);
  }
  for (SerialPort& p : ports) {
    read_usb_facts(roots, p);
    p.board = board_of_usb_id(p.usb_id);
  }
  const auto holders = find_holders(ports);
  for (size_t i = 0; i < ports.size(); ++i) ports[i].holders = holders[i];
  return ports;
}

std::vector<SerialPort> candidate_ports(const std::vector<SerialPort>& ports) {
  std::vector<SerialPort> boards;
  for (const SerialPort& p : ports)
    if (!p.board.empty()) boards.push_back(p);
  return boards.empty() ? ports : boards;
}

std::string describe_port(const SerialPort& p) {
  std::vector<std::string> parts;
  if (p.device != p.path) parts.push_back(p.device);
  if (!p.board.empty()) parts.push_back((p.board == "ST-LINK" ? "looks like an " : "looks like a ") + p.board);
  if (!p.usb_id.empty()) {
    std::string usb = "USB " + p.usb_id;
    const std::string name = p.manufacturer.empty() ? p.product : p.product.empty() ? p.manufacturer
                                                                                    : p.manufacturer + " " + p.product;
    if (!name.empty()) usb += " (" + name + ")";
    parts.push_back(usb);
  }
  if (!p.holders.empty()) {
    std::string busy = "busy: ";
    for (size_t i = 0; i < p.holders.size(); ++i)
      busy += fmt::format("{}PID {} ({})", i ? ", " : "", p.holders[i].pid, p.holders[i].command);
    parts.push_back(busy);
  } else {
    parts.push_back("free");
  }
  std::string out;
  for (size_t i = 0; i < parts.size(); ++i) out += (i ? ", " : "") + parts[i];
  return out;
}

}  // namespace nlsoft::console
