// A chain of Dynamixel servos on a pty: the other end of a board's servo
// bus in QEMU (netduinoplus2's USART1 on -serial pty). Answers as the fake
// chain does (fake_servo_chain.hpp) and logs every goal a servo takes, one
// "ID GOAL" line each, flushed, so a test can hold the goals against what
// the controller computed.
//
//   nlsoft-fake-servo-chain PTY LOG --servo ID:CHIP [--servo ...]
//                           [--fault ID:KIND[:AFTER]]
// KIND: overload, overheating, voltage (the error byte), silent, wrong-id,
// corrupt; AFTER: the moves (goals other than the first it took) the servo
// takes before the fault starts (0): an idle firmware's neutral goals do
// not count, so a fault after AFTER comes that far into a run.
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "shared/chips/catalog.hpp"
#include "tests/firmware/servos/fake_servo_chain.hpp"

namespace {

using nlsoft::test::FakeServoChain;
using nlsoft::test::ServoFault;

struct Pending {
  uint8_t id;
  ServoFault fault;
  uint8_t error;
  uint32_t after;
};

int usage(const char* why) {
  std::fprintf(stderr, "fake servo chain: %s\nusage: PTY LOG --servo ID:CHIP ... [--fault ID:KIND[:AFTER]]\n", why);
  return 2;
}

bool parse_fault(const std::string& spec, Pending& p) {
  const size_t a = spec.find(':');
  if (a == std::string::npos) return false;
  p.id = uint8_t(std::stoi(spec.substr(0, a)));
  const size_t b = spec.find(':', a + 1);
  const std::string kind = spec.substr(a + 1, b == std::string::npos ? std::string::npos : b - a - 1);
  p.after = b == std::string::npos ? 0 : uint32_t(std::stoul(spec.substr(b + 1)));
  p.error = 0;
  if (kind == "overload") p.fault = ServoFault::kError, p.error = 0x20;
  else if (kind == "overheating") p.fault = ServoFault::kError, p.error = 0x04;
  else if (kind == "voltage") p.fault = ServoFault::kError, p.error = 0x01;
  else if (kind == "silent") p.fault = ServoFault::kSilent;
  else if (kind == "wrong-id") p.fault = ServoFault::kWrongId;
  else if (kind == "corrupt") p.fault = ServoFault::kCorrupt;
  else return false;
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage("give the pty and the log file");
  FakeServoChain chain;
  std::vector<Pending> pending;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc) return usage(("no value after " + a).c_str());
    const std::string v = argv[++i];
    if (a == "--servo") {
      const size_t c = v.find(':');
      const nlsoft::chips::ChipSpec* chip = c == std::string::npos ? nullptr : nlsoft::chips::find_chip(v.substr(c + 1).c_str());
      if (chip == nullptr || !nlsoft::chips::on_serial(*chip)) return usage(("not a servo: " + v).c_str());
      chain.servos.emplace_back(uint8_t(std::stoi(v.substr(0, c))), chip->servo_protocol, chip->model_number);
    } else if (a == "--fault") {
      Pending p{};
      if (!parse_fault(v, p)) return usage(("bad fault: " + v).c_str());
      pending.push_back(p);
    } else {
      return usage(("unknown option " + a).c_str());
    }
  }
  const int fd = open(argv[1], O_RDWR | O_NOCTTY);
  if (fd < 0) return usage(("cannot open " + std::string(argv[1]) + ": " + std::strerror(errno)).c_str());
  termios t{};
  if (tcgetattr(fd, &t) == 0) {
    cfmakeraw(&t);
    tcsetattr(fd, TCSANOW, &t);
  }
  FILE* log = std::fopen(argv[2], "w");
  if (log == nullptr) return usage("cannot write the log");
  auto arm = [&]() {
    for (const Pending& p : pending)
      if (nlsoft::test::FakeServo* s = chain.find(p.id); s != nullptr && s->moves >= p.after && s->fault != p.fault) {
        s->fault = p.fault;
        s->error = p.error;
        std::fprintf(log, "fault %d after %u moves\n", p.id, s->moves);
      }
  };
  chain.on_goal = [&](uint8_t id, uint32_t goal) { std::fprintf(log, "%d %u\n", id, goal); };
  arm();
  std::fflush(log);
  for (;;) {
    uint8_t buf[256];
    const ssize_t n = read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EIO) {  // QEMU not attached yet, or gone: wait
      pollfd p{fd, POLLIN, 0};
      poll(&p, 1, 50);
      usleep(20000);
      continue;
    }
    if (n <= 0) break;
    std::vector<uint8_t> answer;
    chain.receive(buf, size_t(n), answer);
    arm();
    std::fflush(log);
    // One write per answer, as a servo sends its packet without a pause.
    if (!answer.empty() && write(fd, answer.data(), answer.size()) < 0) break;
  }
  return 0;
}
