// `nlsoft-console ports` and the port the console picks when given none,
// on a machine of the test's making: pty devices under the names udev gives
// USB boards in /dev/serial/by-id, and a sysfs tree with their USB vendor
// and product ($NLSOFT_SERIAL_BY_ID, $NLSOFT_SYSFS point the console there).
// A port held open by another program (a `sleep` reading it) is named busy,
// with that program's PID and command line.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "app/link/sim_launcher.hpp"
#include "app/support/run_process.hpp"
#include "app/support/temp_dir.hpp"
#include "support/text_checks.hpp"

extern char** environ;

namespace nlsoft::console {
namespace {

using nlsoft::test::contains;

namespace fs = std::filesystem;
using test::run_process;
using test::shell_quote;

constexpr const char* kStLink = "usb-STMicroelectronics_STM32_STLink_066DFF515049657187163930-if02";
constexpr const char* kTeensy = "usb-Teensyduino_USB_Serial_12345670-if00";
constexpr const char* kFtdi = "usb-FTDI_FT232R_USB_UART_A10KZ1B3-if00-port0";

// A pseudo-terminal whose slave side is the "device"; the master stays open
// for the test's length so the slave exists.
struct Pty {
  Pty() {
    master = ::posix_openpt(O_RDWR | O_NOCTTY);
    ::grantpt(master);
    ::unlockpt(master);
    path = ::ptsname(master);
  }
  ~Pty() { ::close(master); }
  int master = -1;
  std::string path;
};

// The machine's view of USB serial ports: by-id links and sysfs folders.
class FakeMachine {
 public:
  FakeMachine() {
    fs::create_directories(by_id());
    fs::create_directories(sysfs() + "/dev/char");
  }
  std::string by_id() const { return dir_.file("serial/by-id"); }
  std::string sysfs() const { return dir_.file("sys"); }
  std::string file(const std::string& name) const { return dir_.file(name); }
  std::string env() const {
    return "NLSOFT_SERIAL_BY_ID=" + shell_quote(by_id()) + " NLSOFT_SYSFS=" + shell_quote(sysfs()) + " ";
  }

  // A USB device on bus 1 port `port` with a CDC-ACM tty that is `device`,
  // laid out as the kernel does: /sys/dev/char/MAJ:MIN ->
  // devices/.../1-N/1-N:1.2/tty/ttyACMk, idVendor in 1-N.
  void usb(const std::string& device, int port, const std::string& vendor, const std::string& product,
           const std::string& manufacturer, const std::string& name) {
    struct stat st {};
    ASSERT_EQ(::stat(device.c_str(), &st), 0) << device;
    const std::string usb = sysfs() + "/devices/pci0000:00/0000:00:14.0/usb1/1-" + std::to_string(port);
    const std::string tty = usb + "/1-" + std::to_string(port) + ":1.2/tty/ttyACM" + std::to_string(port);
    fs::create_directories(tty);
    std::ofstream(usb + "/idVendor") << vendor << "\n";
    std::ofstream(usb + "/idProduct") << product << "\n";
    std::ofstream(usb + "/manufacturer") << manufacturer << "\n";
    std::ofstream(usb + "/product") << name << "\n";
    fs::create_symlink(tty, sysfs() + "/dev/char/" + std::to_string(major(st.st_rdev)) + ":" +
                                std::to_string(minor(st.st_rdev)));
  }
  void link(const std::string& name, const std::string& device) { fs::create_symlink(device, by_id() + "/" + name); }

 private:
  test::TempDir dir_;
};

// Another program with the port open, as a terminal program would have it.
class Holder {
 public:
  explicit Holder(const std::string& device) {
    const std::string cmd = "exec sleep 60 < " + device;
    char* argv[] = {const_cast<char*>("sh"), const_cast<char*>("-c"), const_cast<char*>(cmd.c_str()), nullptr};
    if (::posix_spawnp(&pid_, "sh", nullptr, nullptr, argv, environ) != 0) pid_ = -1;
    // Until sleep runs with the device on its standard input.
    struct stat want {};
    ::stat(device.c_str(), &want);
    for (int i = 0; i < 100 && !holds(want.st_rdev); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ~Holder() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  pid_t pid() const { return pid_; }

 private:
  bool holds(dev_t rdev) const {
    std::ifstream cmdline("/proc/" + std::to_string(pid_) + "/cmdline");
    std::string c((std::istreambuf_iterator<char>(cmdline)), std::istreambuf_iterator<char>());
    struct stat st {};
    return c.rfind("sleep", 0) == 0 && ::stat(("/proc/" + std::to_string(pid_) + "/fd/0").c_str(), &st) == 0 &&
           st.st_rdev == rdev;
  }
  pid_t pid_ = -1;
};

TEST(Ports, ListsByIdNamesWithTheirUsbIdentityAndWhoHoldsThem) {
  FakeMachine m;
  Pty stlink, teensy;
  m.usb(stlink.path, 2, "0483", "374b", "STMicroelectronics", "STM32 STLink");
  m.usb(teensy.path, 3, "16c0", "0483", "Teensyduino", "USB Serial");
  m.link(kStLink, stlink.path);
  m.link(kTeensy, teensy.path);
  Holder holder(stlink.path);
  ASSERT_GT(holder.pid(), 0);

  const auto r = run_process(m.env() + NLSOFT_CONSOLE_BIN " ports --json");
  ASSERT_EQ(r.code, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << r.output;
  ASSERT_EQ(j["ports"].size(), 2u) << r.output;
  const auto& st = j["ports"][0];
  EXPECT_EQ(st["path"], m.by_id() + "/" + kStLink);
  EXPECT_EQ(st["device"], stlink.path);
  EXPECT_EQ(st["usb_id"], "0483:374b");
  EXPECT_EQ(st["board"], "ST-LINK");
  EXPECT_EQ(st["manufacturer"], "STMicroelectronics");
  EXPECT_EQ(st["busy"], true);
  ASSERT_EQ(st["holders"].size(), 1u) << r.output;
  EXPECT_EQ(st["holders"][0]["pid"], holder.pid());
  EXPECT_EQ(st["holders"][0]["command"], "sleep 60");
  const auto& te = j["ports"][1];
  EXPECT_EQ(te["path"], m.by_id() + "/" + kTeensy);
  EXPECT_EQ(te["usb_id"], "16c0:0483");
  EXPECT_EQ(te["board"], "Teensy");
  EXPECT_EQ(te["busy"], false);
  EXPECT_TRUE(te["holders"].empty());

  const auto text = run_process(m.env() + NLSOFT_CONSOLE_BIN " ports");
  ASSERT_EQ(text.code, 0) << text.output;
  EXPECT_TRUE(contains(text.output, m.by_id() + "/" + kStLink + "\n    " + stlink.path +
                                        ", looks like an ST-LINK, USB 0483:374b (STMicroelectronics STM32 STLink), "
                                        "busy: PID " + std::to_string(holder.pid()) + " (sleep 60)"))
      << text.output;
  EXPECT_TRUE(contains(text.output, m.by_id() + "/" + kTeensy + "\n    " + teensy.path +
                                        ", looks like a Teensy, USB 16c0:0483 (Teensyduino USB Serial), free"))
      << text.output;
}

TEST(Ports, NoPortsIsSaidWithWhereItLooked) {
  FakeMachine m;
  const auto r = run_process(m.env() + NLSOFT_CONSOLE_BIN " ports");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "no serial ports found (looked in " + m.by_id())) << r.output;
  const auto j = run_process(m.env() + NLSOFT_CONSOLE_BIN " ports --json");
  EXPECT_EQ(nlohmann::json::parse(j.output, nullptr, false), nlohmann::json::parse(R"({"ports": []})")) << j.output;
}

// Without a PORT, --sim or --qemu: the one port that looks like a board is
// taken (a USB-serial adapter beside it does not count), and named; with
// two boards, or none, the console says so, lists them and connects to
// nothing.
TEST(Ports, ALoneBoardIsTheDefaultPortAndSeveralAreListed) {
  ::setenv("NLSOFT_FIRMWARE_SIM", NLSOFT_FIRMWARE_SIM_BIN, 1);
  FakeMachine m;
  SimLauncher sim;
  const std::string board = sim.start("hasel");
  m.usb(board, 2, "0483", "374b", "STMicroelectronics", "STM32 STLink");
  m.link(kStLink, board);
  Pty adapter;
  m.link(kFtdi, adapter.path);  // no sysfs facts: an unknown adapter
  const std::string script = m.file("get.nls");
  std::ofstream(script) << "get r\n";
  const std::string console = m.env() + NLSOFT_CONSOLE_BIN " --no-record --script " + shell_quote(script);

  const auto one = run_process(console);
  EXPECT_EQ(one.code, 0) << one.output;
  EXPECT_TRUE(contains(one.output, "nlsoft-console: no port given; connecting to the only board found: " + m.by_id() +
                                       "/" + kStLink + " (" + board + ", looks like an ST-LINK"))
      << one.output;
  EXPECT_TRUE(contains(one.output, "connected: nlsoft-posix")) << one.output;

  Pty teensy;
  m.usb(teensy.path, 3, "16c0", "0483", "Teensyduino", "USB Serial");
  m.link(kTeensy, teensy.path);
  const auto two = run_process(console);
  EXPECT_EQ(two.code, 2) << two.output;
  EXPECT_TRUE(contains(two.output, "nothing to connect to: 2 ports could be the board, give one")) << two.output;
  EXPECT_TRUE(contains(two.output, "\n  " + m.by_id() + "/" + kStLink + "  (")) << two.output;
  EXPECT_TRUE(contains(two.output, "\n  " + m.by_id() + "/" + kTeensy + "  (")) << two.output;
  EXPECT_FALSE(contains(two.output, "connected:")) << two.output;

  for (const auto& e : fs::directory_iterator(m.by_id())) fs::remove(e.path());
  const auto none = run_process(console);
  EXPECT_EQ(none.code, 2) << none.output;
  EXPECT_TRUE(contains(none.output, "nothing to connect to: no serial port found (looked in " + m.by_id())) << none.output;
}

}  // namespace
}  // namespace nlsoft::console
