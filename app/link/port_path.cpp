#include "app/link/port_path.hpp"

#include <sys/stat.h>

#include <filesystem>
#include <thread>

namespace nlsoft::console {

namespace fs = std::filesystem;

std::string stable_port_path(const std::string& port, const std::string& by_id_dir) {
  std::error_code ec;
  const fs::path dir(by_id_dir);
  if (fs::path(port).parent_path() == dir) return port;
  const fs::path device = fs::canonical(port, ec);
  if (ec) return port;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::error_code e2;
    if (!entry.is_symlink(e2)) continue;
    if (fs::canonical(entry.path(), e2) == device && !e2) return entry.path().string();
  }
  return port;
}

bool wait_for_port(const std::string& path, std::chrono::milliseconds limit, const std::function<bool()>& give_up) {
  // Polling, not inotify: the by-id folder itself may not exist until the
  // first USB serial device appears, and 100 ms is quick enough for a human.
  const auto until = std::chrono::steady_clock::now() + limit;
  while (true) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0) return true;
    if (give_up && give_up()) return false;
    if (limit.count() >= 0 && std::chrono::steady_clock::now() >= until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

}  // namespace nlsoft::console
