#pragma once
// Which serial ports this machine has, what is on them and who holds them,
// for `nlsoft-console ports` and for picking the port when none is given:
// the udev names in /dev/serial/by-id, USB ttys without one (ttyACM*,
// ttyUSB*), the USB vendor and product from sysfs (an ST-LINK of a Nucleo
// board, a Teensy), and the processes that have the device open
// (/proc/*/fd), as `tio --list` and MAVProxy's autodetect look.
#include <string>
#include <vector>

namespace nlsoft::console {

struct PortHolder {
  int pid = 0;
  std::string command;  // its command line, or its name when that is unreadable
};

struct SerialPort {
  std::string path;    // what to give the console: the by-id name when there is one
  std::string device;  // what it resolves to (/dev/ttyACM0)
  std::string usb_id;  // "0483:374b", empty when sysfs does not say
  std::string manufacturer, product, serial;
  std::string board;   // "ST-LINK" or "Teensy" when it looks like one, else empty
  std::vector<PortHolder> holders;  // processes (other than this one) with it open
};

// Where the facts are read: udev's by-id folder and the sysfs root. The
// environment overrides both ($NLSOFT_SERIAL_BY_ID, $NLSOFT_SYSFS) so a
// test can point them at a tree of its own.
struct PortRoots {
  std::string by_id = "/dev/serial/by-id";
  std::string sysfs = "/sys";
  static PortRoots from_environment();
};

// Every port found, by-id names first (sorted), then USB ttys without one.
std::vector<SerialPort> list_serial_ports(const PortRoots& roots);

// "ST-LINK" for ST's debug probes (0483:3748, 374b, ...), "Teensy" for
// PJRC's serial modes (16c0:0483, ...); else empty.
std::string board_of_usb_id(const std::string& usb_id);

// The ports worth connecting to without being told: those that look like a
// board the firmware runs on, or, when none does, every port found.
std::vector<SerialPort> candidate_ports(const std::vector<SerialPort>& ports);

// "ST-LINK, USB 0483:374b, busy: PID 42 (nlsoft-console ...)": one line of
// what is known about a port, after its path.
std::string describe_port(const SerialPort& p);

}  // namespace nlsoft::console
