#pragma once
// The posix HAL: serial over a pty master, a 1 MHz tick from the monotonic
// clock, and a simulated plant in the loop as the actuators and sensors
// (sim_plant_hal.hpp).
#include <errno.h>
#include <time.h>
#include <unistd.h>

#include "firmware/ports/posix/sim_plant_hal.hpp"

namespace nlsoft::fw::posix {

class SimHal final : public SimPlantHal {
 public:
  explicit SimHal(int fd) : fd_(fd) {}

  // What the port's last ppoll said: reads are tried only when bytes are
  // there, and a short read means they have all been taken. An idle
  // simulator so makes no failing read() at all.
  void set_readable(bool readable) { readable_ = readable; }

  size_t serial_read(uint8_t* buf, size_t cap) override {
    if (!readable_) return 0;
    const ssize_t r = ::read(fd_, buf, cap);
    if (r > 0) bytes_in_ += size_t(r);
    if (r < ssize_t(cap)) readable_ = false;
    return r > 0 ? size_t(r) : 0;
  }
  size_t serial_write(const uint8_t* data, size_t len) override {
    const ssize_t w = ::write(fd_, data, len);
    if (w >= 0) return size_t(w);
    // EAGAIN: the pty is full (the console is slow): keep the bytes queued.
    // Anything else (no reader at all): drop them, as a UART would.
    return errno == EAGAIN ? 0 : len;
  }
  uint32_t ticks() override {
    timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return uint32_t(uint64_t(ts.tv_sec) * 1000000u + uint64_t(ts.tv_nsec) / 1000u);
  }
  uint32_t tick_rate_hz() const override { return 1000000u; }

 private:
  int fd_;
  size_t bytes_in_ = 0;
  bool readable_ = false;  // until ppoll says so
};

}  // namespace nlsoft::fw::posix
