#pragma once
// The hardware-abstraction layer: the only thing a port implements. Serial
// bytes in and out (non-blocking), a free-running tick counter, the
// actuators, the sensors, and - on simulated or hardware-in-the-loop rigs -
// the true output for telemetry.
#include <cstddef>
#include <cstdint>

namespace nlsoft::fw {

class Hal {
 public:
  // Up to cap received bytes; 0 when none are waiting. Never blocks.
  virtual size_t serial_read(uint8_t* buf, size_t cap) = 0;
  // Queues up to len bytes for sending; returns how many were taken (fewer
  // when the port's transmit buffer is full). Never blocks.
  virtual size_t serial_write(const uint8_t* data, size_t len) = 0;
  // Free-running counter at tick_rate_hz(); wraps at 2^32.
  virtual uint32_t ticks() = 0;
  virtual uint32_t tick_rate_hz() const = 0;
  virtual void actuate(const float* u, int m) = 0;
  virtual void read_sensors(float* l, int w) = 0;
  // The true end-effector output when the port can observe it (simulated
  // plant, motion capture); false on a plain board. Telemetry only: the
  // controller never sees it unless its feedback parameter says so.
  virtual bool read_output(float* y, int n) = 0;
  // A run or an identification run begins. A simulated plant starts its
  // noise over from its seed here, so the same commands give the same data
  // however long the port idled before; a board has nothing to do.
  virtual void run_begins() {}

 protected:
  ~Hal() = default;
};

}  // namespace nlsoft::fw
