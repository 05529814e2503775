#pragma once
// Which path to open for a port, and waiting for one that is not there yet.
// A USB serial device can come back under another /dev/ttyACMn after a
// replug or a board reset; udev's /dev/serial/by-id names it by vendor,
// product and serial number, so a console that opened that name reconnects
// to the same board, wherever it re-enumerates.
#include <chrono>
#include <functional>
#include <string>

namespace nlsoft::console {

constexpr const char* kSerialByIdDir = "/dev/serial/by-id";

// The by-id link (in `by_id_dir`) that resolves to the same device as
// `port`, or `port` itself when there is none (a pty, a built-in UART, a
// system without udev) or `port` already is one.
std::string stable_port_path(const std::string& port, const std::string& by_id_dir = kSerialByIdDir);

// Polls until `path` exists (true) or `limit` passes, or `give_up()` says
// so (false). A negative limit waits until give_up().
bool wait_for_port(const std::string& path, std::chrono::milliseconds limit, const std::function<bool()>& give_up);

}  // namespace nlsoft::console
