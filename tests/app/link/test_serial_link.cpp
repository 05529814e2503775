// The byte pipe's guards: a port is a terminal held by one console alone,
// and nothing written before a close reaches the port opened next.
#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "app/link/link_error.hpp"
#include "app/link/port_path.hpp"
#include "app/link/serial_link.hpp"
#include "app/support/temp_dir.hpp"

using namespace nlsoft::console;

namespace {

struct Pty {
  int master = -1, slave = -1;
  std::string path;
  Pty() {
    char name[128];
    termios raw{};
    cfmakeraw(&raw);
    if (openpty(&master, &slave, name, &raw, nullptr) != 0) throw std::runtime_error("openpty failed");
    path = name;
  }
  ~Pty() {
    ::close(master);
    ::close(slave);
  }
  // Bytes that arrive at the master within `ms`.
  std::vector<uint8_t> drain(int ms) {
    std::vector<uint8_t> got;
    pollfd p{master, POLLIN, 0};
    while (poll(&p, 1, ms) > 0) {
      uint8_t buf[256];
      const ssize_t n = ::read(master, buf, sizeof buf);
      if (n <= 0) break;
      got.insert(got.end(), buf, buf + n);
    }
    return got;
  }
};

std::string open_error(const std::string& path) {
  SerialLink link;
  try {
    link.open(path, 115200, {});
  } catch (const LinkError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(SerialLink, APortHeldByAnotherProgramIsRefusedNamingIt) {
  Pty pty;
  int ready[2];
  ASSERT_EQ(pipe(ready), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {  // another console: holds the port until killed
    SerialLink holder;
    holder.open(pty.path, 115200, {});
    const char ok = 1;
    (void)!write(ready[1], &ok, 1);
    pause();
    _exit(0);
  }
  char ok = 0;
  ASSERT_EQ(read(ready[0], &ok, 1), 1);
  const std::string why = open_error(pty.path);
  kill(child, SIGKILL);
  waitpid(child, nullptr, 0);
  EXPECT_NE(why.find("port busy: " + pty.path + " is held by PID " + std::to_string(child)), std::string::npos) << why;
  // and free again once the holder is gone
  EXPECT_EQ(open_error(pty.path), "");
}

TEST(SerialLink, WhatIsNotATerminalIsNamed) {
  EXPECT_EQ(open_error("/dev/null"), "not a serial port: /dev/null is a character device that is not a terminal");
  nlsoft::test::TempDir dir;
  const std::string file = dir.file("port");
  std::FILE* f = std::fopen(file.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fclose(f);
  EXPECT_EQ(open_error(file), "not a serial port: " + file + " is a regular file");
}

TEST(SerialLink, BytesWrittenAfterACloseNeverReachTheNextPort) {
  Pty pty;
  SerialLink link;
  link.open(pty.path, 115200, {});
  pty.drain(100);
  link.close();
  link.write({0x11, 0x22, 0x33});  // posted to a stopped link
  link.open(pty.path, 115200, {});
  link.write({0x44});
  std::vector<uint8_t> got;
  for (int tries = 0; tries < 50 && (got.empty() || got.back() != 0x44); ++tries) {
    const auto more = pty.drain(20);
    got.insert(got.end(), more.begin(), more.end());
  }
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got.back(), 0x44);
  for (uint8_t b : got) EXPECT_TRUE(b != 0x11 && b != 0x22 && b != 0x33) << "stale byte " << int(b);
}

// A USB board that re-enumerates as another ttyACMn keeps its by-id name: the
// console opens that name when there is one, so a reconnect finds the board.
TEST(PortPath, APortIsOpenedByItsByIdNameWhenItHasOne) {
  Pty board, other;
  nlsoft::test::TempDir by_id;
  const std::string link = by_id.file("usb-nlsoft_board_0042-if00");
  ASSERT_EQ(::symlink(board.path.c_str(), link.c_str()), 0);
  ASSERT_EQ(::symlink("/dev/null", by_id.file("usb-something-else").c_str()), 0);
  EXPECT_EQ(stable_port_path(board.path, by_id.path), link);
  EXPECT_EQ(stable_port_path(link, by_id.path), link) << "a by-id name is kept";
  EXPECT_EQ(stable_port_path(other.path, by_id.path), other.path) << "no link: the path as given";
  EXPECT_EQ(stable_port_path(board.path, by_id.file("missing-folder")), board.path);
}

TEST(PortPath, WaitingForAPortEndsWhenItAppearsOrTheLimitPasses) {
  nlsoft::test::TempDir dir;
  const std::string path = dir.file("ttyACM9");
  EXPECT_FALSE(wait_for_port(path, std::chrono::milliseconds(200), {}));
  bool asked = false;
  EXPECT_FALSE(wait_for_port(path, std::chrono::milliseconds(-1), [&] { return asked = true; }))
      << "give_up ends an unlimited wait";
  EXPECT_TRUE(asked);
  std::thread plug([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (f) std::fclose(f);
  });
  EXPECT_TRUE(wait_for_port(path, std::chrono::milliseconds(-1), {}));
  plug.join();
}
