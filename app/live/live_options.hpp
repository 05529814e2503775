#pragma once
// How a live console connects: the port or the simulator it starts, where
// it records, and how the link behaves (the options of `nlsoft-console`,
// `tune` and `ident`, read by connect_args.cpp).
#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "app/link/port_path.hpp"
#include "app/link/session.hpp"
#include "host/rig/board_table.hpp"
#include "host/rig/rig.hpp"

namespace nlsoft::console {

struct LiveOptions {
  std::string port;          // a serial device, or empty with sim_rig/qemu_image
  unsigned baud = 115200;
  std::string qemu_image;    // with sim_in_qemu: the HIL image of the rig (built from its file)
  std::string sim_rig;       // a rig file: start nlsoft-firmware-sim for it (a path: the child loads it)
  // The rig the board runs, loaded once by live_options; nullptr: the
  // shipped rig the firmware names.
  std::shared_ptr<const host::Rig> rig;
  bool sim_in_qemu = false;  // ... or boot the Cortex-M4F image in QEMU instead
  std::string qemu_board = host::kDefaultQemuBoard;  // whose image: a board of qemu_board_names()
  std::vector<std::string> sim_args;
  std::string db_path;       // empty: default_db_path()
  bool record = true;        // false: a temporary database, deleted on exit
  // --db-busy: how long samples wait in memory for a database another
  // process has locked before they are counted lost (Recorder::Options).
  std::chrono::milliseconds db_busy{30000};
  int decimation = 0;        // 0: 1 on a simulator, else what the baud rate carries
  // --wait: how long to wait for a port that is not there yet (a board
  // being plugged in); 0: fail at once; negative: until Ctrl-C.
  std::chrono::milliseconds wait{0};
  std::string by_id_dir = kSerialByIdDir;  // where udev names USB devices (tests point it elsewhere)
  std::string udp;  // HOST:PORT: stream every telemetry sample there as JSON (PlotJuggler)
  SessionOptions session;
};

}  // namespace nlsoft::console
