#pragma once
// The buses a sensor chip hangs on, as the chip drivers see them. A port
// implements them over its controllers (ports/*/i2c_*.cpp, spi_*.cpp); the
// tests implement them as register-level fakes of the chips. Every wait
// inside a transaction is bounded: a bus that hangs (SDA held low, a chip
// that never answers) ends in kTimeout, never in a stuck control loop.
#include <cstddef>
#include <cstdint>

namespace nlsoft::fw::drivers {

enum class BusStatus : uint8_t {
  kOk = 0,
  kNack = 1,      // I²C: no chip acknowledged its address or a byte
  kTimeout = 2,   // a flag the transaction waits on did not come in its bound
  kBusError = 3,  // the controller reported an error (arbitration lost, overrun, mode fault)
};

// An I²C master. START, addr7+W, `wn` bytes from `w`; then, when rn > 0, a
// repeated START, addr7+R, `rn` bytes into `r`; STOP. wn == rn == 0 probes
// the address (kOk: a chip answered).
class I2cBus {
 public:
  virtual BusStatus write_read(uint8_t addr7, const uint8_t* w, size_t wn, uint8_t* r, size_t rn) = 0;

 protected:
  ~I2cBus() = default;
};

// Who a SPI transaction talks to: the chip-select line (the port's index
// into its chip-select table), the clock mode (CPOL << 1 | CPHA) and the
// highest clock the chip takes.
struct SpiTarget {
  uint8_t cs = 0;
  uint8_t mode = 0;
  uint32_t max_clock_hz = 1000000;
};

// A SPI master: chip select asserted, `n` bytes full duplex (`rx` may be
// null when the answer is not wanted), chip select released.
class SpiBus {
 public:
  virtual BusStatus transfer(const SpiTarget& target, const uint8_t* tx, uint8_t* rx, size_t n) = 0;

 protected:
  ~SpiBus() = default;
};

// A single-wire half-duplex serial bus: a chain of servos (Dynamixel).
// exchange() waits for what was sent before to leave, sends `n` bytes, then
// gathers the answer into `rx` until the line stays quiet for the port's gap
// (a few byte times past the servos' return delay) or `cap` bytes came; the
// port drops the line's echo of its own bytes. `got` says how many came: 0
// is a silent bus (kTimeout). n == 0 only listens (for an answer still on
// its way). send() queues bytes and returns at once: the
// step's broadcast SYNC_WRITE, which no servo answers.
class SerialBus {
 public:
  virtual BusStatus exchange(const uint8_t* tx, size_t n, uint8_t* rx, size_t cap, size_t& got) = 0;
  virtual BusStatus send(const uint8_t* tx, size_t n) = 0;

 protected:
  ~SerialBus() = default;
};

}  // namespace nlsoft::fw::drivers
