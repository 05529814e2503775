// The boards' I²C and SPI masters against chip models nobody here wrote:
// the bus probe images (bus_probe/) in qemu-system-arm with QEMU 7.2's
// lsm303dlhc_mag, dps310 and max1111 attached. On mps2-an386 the I²C chips
// land on the shield1 SBCON bus (the default for -device; buses.hpp) and
// the ADC on the ADC PL022; on netduinoplus2 the ADC lands on QEMU's sixth
// SPI controller, driven by the stm32f4 port's SPI master. Skipped where
// qemu-system-arm or the cross-built images are absent.
#include <fcntl.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <termios.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include "qemu_process.hpp"

using namespace nlsoft::test;

namespace {

// A probe image's report: each line's first word -> the rest of the line.
using Report = std::map<std::string, std::string>;

// QEMU's machine protocol over a unix socket: enough for qom-set.
class Qmp {
 public:
  explicit Qmp(const std::string& path) {
    for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
      const int fd = socket(AF_UNIX, SOCK_STREAM, 0);
      sockaddr_un a{};
      a.sun_family = AF_UNIX;
      std::snprintf(a.sun_path, sizeof a.sun_path, "%s", path.c_str());
      if (connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) {
        fd_ = fd;
        break;
      }
      close(fd);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    if (fd_ < 0) return;
    (void)line();  // the greeting
    (void)command(R"({"execute": "qmp_capabilities"})");
  }
  ~Qmp() {
    if (fd_ >= 0) close(fd_);
  }
  bool ok() const { return fd_ >= 0; }
  // The reply line (events in between are skipped).
  std::string command(const std::string& json) {
    const std::string out = json + "\n";
    if (write(fd_, out.data(), out.size()) != ssize_t(out.size())) return "";
    for (;;) {
      const std::string l = line();
      if (l.empty() || l.find("\"event\"") == std::string::npos) return l;
    }
  }
  std::string qom_set(const std::string& path, const std::string& property, long value) {
    return command(R"({"execute": "qom-set", "arguments": {"path": ")" + path + R"(", "property": ")" + property +
                   R"(", "value": )" + std::to_string(value) + "}}");
  }

 private:
  std::string line() {
    std::string l;
    char c;
    pollfd p{fd_, POLLIN, 0};
    while (poll(&p, 1, 5000) == 1 && read(fd_, &c, 1) == 1 && c != '\n') l += c;
    return l;
  }
  int fd_ = -1;
};

class BusProbe : public ::testing::Test {
 protected:
  void TearDown() override {
    qmp_.reset();
    if (pty_ >= 0) close(pty_);
    qemu_.reset();
    std::remove(qmp_path_.c_str());
  }
  void boot(const std::string& elf, const std::string& board, std::vector<std::string> devices) {
    if (!qemu_arm_available()) GTEST_SKIP() << "qemu-system-arm is not installed: the bus probe test needs it";
    if (!std::ifstream(elf).good())
      GTEST_SKIP() << elf << " was not built (arm-none-eabi-g++ missing when configuring)";
    qmp_path_ = ::testing::TempDir() + "nlsoft-bus-probe-" + std::to_string(getpid()) + ".qmp";
    std::remove(qmp_path_.c_str());
    devices.insert(devices.end(), {"-qmp", "unix:" + qmp_path_ + ",server=on,wait=off"});
    qemu_ = std::make_unique<QemuProcess>(elf, board, devices);
    ASSERT_FALSE(qemu_->path().empty()) << "QEMU reported no pty:\n" << qemu_->log();
    pty_ = open(qemu_->path().c_str(), O_RDWR | O_NOCTTY);
    ASSERT_GE(pty_, 0) << qemu_->path();
    termios t{};
    tcgetattr(pty_, &t);
    cfmakeraw(&t);
    tcsetattr(pty_, TCSANOW, &t);
  }
  Qmp& qmp() {
    if (!qmp_) qmp_ = std::make_unique<Qmp>(qmp_path_);
    return *qmp_;
  }
  // Asks ('r' and a tag of this ask's own, again every 250 ms until the
  // image answers: it may still be booting or busy) and reads reports up
  // to their "end" line until one repeats the tag. A report that answers an
  // earlier ask's repeated request (read before this ask's changes were
  // made, a busy image under load) is dropped.
  Report ask() {
    const std::string tag(1, char('A' + asks_++ % 26));
    const std::string request = "r" + tag;
    std::string text;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(40);
    auto last_ask = std::chrono::steady_clock::time_point{};
    while (std::chrono::steady_clock::now() < deadline) {
      if (const size_t end = text.find("end\n"); end != std::string::npos) {
        Report r = parse(text.substr(0, end + 4));
        if (r["tag"] == tag) return r;
        text.erase(0, end + 4);
        continue;
      }
      if (text.empty() && std::chrono::steady_clock::now() - last_ask > std::chrono::milliseconds(250)) {
        if (write(pty_, request.data(), request.size()) != ssize_t(request.size())) break;
        last_ask = std::chrono::steady_clock::now();
      }
      pollfd p{pty_, POLLIN, 0};
      char buf[256];
      if (poll(&p, 1, 100) == 1) {
        const ssize_t n = read(pty_, buf, sizeof buf);
        if (n > 0) text.append(buf, size_t(n));
      }
    }
    ADD_FAILURE() << "no whole report tagged " << tag << " from the image; got:\n" << text;
    return parse(text);
  }
  static Report parse(const std::string& text) {
    Report r;
    std::istringstream lines(text);
    std::string l;
    while (std::getline(lines, l)) {
      const auto space = l.find(' ');
      r[l.substr(0, space)] = space == std::string::npos ? "" : l.substr(space + 1);
    }
    return r;
  }
  int asks_ = 0;
  std::unique_ptr<QemuProcess> qemu_;
  std::unique_ptr<Qmp> qmp_;
  std::string qmp_path_;
  int pty_ = -1;
};

// 1 = 0.001 µT in QEMU's property; 1 gauss = 100 µT; the model's default
// gain (CRB GN = 1, ±1.3 gauss) is 1100 LSB/gauss on X and Y, 980 on Z
// (datasheet table 3), truncated toward zero as the model does.
long raw_xy(long millimicrotesla) { return millimicrotesla * 1100 / 100000; }
long raw_z(long millimicrotesla) { return millimicrotesla * 980 / 100000; }

std::string mag_line(long x, long y, long z) {
  return "0 " + std::to_string(raw_xy(x)) + " " + std::to_string(raw_xy(y)) + " " + std::to_string(raw_z(z));
}

}  // namespace

TEST_F(BusProbe, An386MastersReadTheMagnetometerPressureSensorAndAdcModels) {
  boot(NLSOFT_M4_IMAGE_DIR "/nlsoft-m4-bus-probe.elf", "mps2-an386",
       {"-device", "lsm303dlhc_mag,id=mag,address=0x1e", "-device", "dps310,address=0x77", "-device",
        "max1111,input0=0x5a,input1=0x33"});
  if (IsSkipped() || HasFatalFailure()) return;
  Report r = ask();
  EXPECT_EQ(r["mag_id"], "0 48 34 33") << "IRA/IRB/IRC: 'H', '4', '3'";
  EXPECT_EQ(r["mag_xyz"], "0 0 0 0");
  // DPS310: the model leaves PRODUCT_ID (0x0D) unserved (0xff); its
  // measurement configuration (all ready) and the fixed calibration
  // coefficients of its reset state, read in one 18-byte burst.
  EXPECT_EQ(r["dps310_id"], "0 ff");
  EXPECT_EQ(r["dps310_meas_cfg"], "0 f0");
  EXPECT_EQ(r["dps310_coef"], "0 0e 1e dd 13 ca 5f 21 52 f9 c6 04 d1 db 47 00 5b fb 3a");
  // Nobody at 0x50: NACK at once, probe or read; the magnetometer is not on shield0.
  EXPECT_EQ(r["nobody_probe"], "1");
  EXPECT_EQ(r["nobody_read"], "1");
  EXPECT_EQ(r["shield0_mag"], "1");
  // Left mid-byte with the chip holding SDA low (SCL high: lines 1), the
  // next read runs the master's recovery (clocks until SDA is free, STOP)
  // and reads the identity. QEMU's bit-bang model would also take a START
  // over the stranded chip, so this shows the recovery completes and leaves
  // the bus working, not that a real chip needed it.
  EXPECT_EQ(r["stranded_lines"], "1");
  EXPECT_EQ(r["recovered_mag_id"], "0 48 34 33");
  // MAX1111, single-ended unipolar: the 8-bit result as (r >> 2) & 0x3f, then r << 6.
  EXPECT_EQ(r["adc_00"], "0 00 16 80") << "input0 = 0x5a";
  EXPECT_EQ(r["adc_40"], "0 00 0c c0") << "input1 = 0x33";
  EXPECT_EQ(r["spi_xfer7"], "0 961538") << "1 MHz at most from 25 MHz: 25 MHz / (2 * 13)";
  EXPECT_EQ(r["spi_other_cs"], "3") << "a PL022 has one chip select";

  ASSERT_TRUE(qmp().ok()) << "no QMP socket at " << qmp_path_;
  for (const auto& [x, y, z] : {std::tuple{100000L, 50000L, 25000L}, std::tuple{1000L, 180000L, 7000L}}) {
    ASSERT_NE(qmp().qom_set("/machine/peripheral/mag", "mag-x", x).find("return"), std::string::npos);
    ASSERT_NE(qmp().qom_set("/machine/peripheral/mag", "mag-y", y).find("return"), std::string::npos);
    ASSERT_NE(qmp().qom_set("/machine/peripheral/mag", "mag-z", z).find("return"), std::string::npos);
    r = ask();
    EXPECT_EQ(r["mag_xyz"], mag_line(x, y, z)) << "x " << x << ", y " << y << ", z " << z;
    EXPECT_EQ(r["mag_id"], "0 48 34 33");
  }
}

TEST_F(BusProbe, An386ReportsChipsThatDoNotAnswer) {
  // No magnetometer; a dps310 without address= sits at 0, the general call
  // address, and answers nowhere else.
  boot(NLSOFT_M4_IMAGE_DIR "/nlsoft-m4-bus-probe.elf", "mps2-an386", {"-device", "dps310"});
  if (IsSkipped() || HasFatalFailure()) return;
  Report r = ask();
  EXPECT_EQ(r["mag_id"], "1 00 00 00");
  EXPECT_EQ(r["mag_xyz"].substr(0, 2), "1 ");
  EXPECT_EQ(r["dps310_id"], "1 00");
  EXPECT_EQ(r["nobody_probe"], "1");
  // No ADC on the SPI bus: the controller still clocks the bytes (MISO reads 0).
  EXPECT_EQ(r["adc_00"], "0 00 00 00");
}

TEST_F(BusProbe, Stm32f4MastersInNetduinoplus2) {
  boot(NLSOFT_STM32F4_IMAGE_DIR "/nlsoft-stm32f4-bus-probe.elf", "stm32f4",
       {"-device", "max1111,input0=0x5a,input1=0x33"});
  if (IsSkipped() || HasFatalFailure()) return;
  Report r = ask();
  // QEMU 7.2's STM32 SPI model clocks a second frame on every read of DR,
  // sending back the byte just received; so each byte the master reads is
  // the ADC's answer to that second frame: the conversion's high bits
  // (0x5a >> 2, 0x33 >> 2), then zeros (the low bits went out as a control
  // byte with START set and powered the converter down).
  EXPECT_EQ(r["adc_00"], "0 16 00 00");
  EXPECT_EQ(r["adc_40"], "0 0c 00 00");
  std::istringstream xfer(r["spi_xfer7"]);
  int status = -1;
  long rate = 0;
  xfer >> status >> rate;
  EXPECT_EQ(status, 0);
  EXPECT_LE(rate, 1000000) << "never above the chip's 1 MHz";
  EXPECT_GT(rate, 500000) << "the fastest power-of-two prescaler at or below it";
  for (const char* bus : {"spi1", "spi2"}) {
    std::istringstream l(r[bus]);
    std::string a, b;
    l >> status >> a >> b >> rate;
    EXPECT_EQ(status, 0) << bus;
    EXPECT_EQ(a + b, "0000") << bus << ": nothing attached reads 0";
    EXPECT_LE(rate, 10000000) << bus;
    EXPECT_GT(rate, 5000000) << bus;
  }
  EXPECT_EQ(r["spi_bad_cs"], "3") << "a chip select past the board's table";
  // No I2C1 model (its registers read 0): START never shows, the master gives up.
  EXPECT_EQ(r["i2c1"].substr(0, 2), "2 ") << r["i2c1"];
}
