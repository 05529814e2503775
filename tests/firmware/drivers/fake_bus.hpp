#pragma once
// Register-level fakes of sensor chips on fake I²C and SPI masters. A fake
// chip is a register file with its chip's addressing rules (SPI read and
// auto-increment bits, I²C auto-increment bit or none, pointer wrap) and
// switches for what the drivers must survive: absent, wrong identity,
// stopped answering. The buses count transactions per chip.
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "firmware/drivers/bus.hpp"

namespace nlsoft::fw::drivers::fake {

// Something on a bus: answers an I²C transaction or a SPI transfer.
class Device {
 public:
  virtual ~Device() = default;
  virtual BusStatus i2c(const uint8_t* w, size_t wn, uint8_t* r, size_t rn) = 0;
  virtual void spi(const uint8_t* tx, uint8_t* rx, size_t n) = 0;

  bool present = true;     // false: NACK on I²C, MISO at miso_idle on SPI
  uint8_t miso_idle = 0xFF;  // what an undriven MISO reads (pull-up: 0xFF)
  int transactions = 0;
};

class I2c final : public I2cBus {
 public:
  void attach(uint8_t addr7, Device* d) { devices_[addr7] = d; }
  BusStatus write_read(uint8_t addr7, const uint8_t* w, size_t wn, uint8_t* r, size_t rn) override {
    ++transactions;
    auto it = devices_.find(addr7);
    if (it == devices_.end() || !it->second->present) return BusStatus::kNack;
    ++it->second->transactions;
    return it->second->i2c(w, wn, r, rn);
  }
  int transactions = 0;

 private:
  std::map<uint8_t, Device*> devices_;
};

class Spi final : public SpiBus {
 public:
  void attach(uint8_t cs, Device* d) { devices_[cs] = d; }
  BusStatus transfer(const SpiTarget& target, const uint8_t* tx, uint8_t* rx, size_t n) override {
    ++transactions;
    last_target = target;
    std::vector<uint8_t> in(n, 0xFF);
    auto it = devices_.find(target.cs);
    if (it != devices_.end() && it->second->present) {
      ++it->second->transactions;
      it->second->spi(tx, in.data(), n);
    } else {
      const uint8_t idle = it == devices_.end() ? uint8_t{0xFF} : it->second->miso_idle;
      for (auto& b : in) b = idle;
    }
    if (rx != nullptr)
      for (size_t i = 0; i < n; ++i) rx[i] = in[i];
    return status;
  }
  int transactions = 0;
  SpiTarget last_target{};
  BusStatus status = BusStatus::kOk;  // what every transfer reports (a controller fault)

 private:
  std::map<uint8_t, Device*> devices_;
};

// A chip of 8-bit registers addressed by the first byte of a transaction.
class RegisterChip : public Device {
 public:
  struct Rules {
    uint8_t spi_read_bit;       // set in the first byte: a read
    uint8_t spi_increment_bit;  // set: the address advances (0: see always_increment)
    uint8_t i2c_increment_bit;  // likewise on I²C
    bool always_increment;      // the address advances whatever the bits
  };

  explicit RegisterChip(Rules rules) : rules_(rules) { regs.fill(0); }

  BusStatus i2c(const uint8_t* w, size_t wn, uint8_t* r, size_t rn) override {
    if (wn == 0) return BusStatus::kOk;
    const bool inc = rules_.always_increment || (w[0] & rules_.i2c_increment_bit) != 0;
    const uint8_t reg = static_cast<uint8_t>(w[0] & ~rules_.i2c_increment_bit);
    access(reg, inc, w + 1, wn - 1, r, rn);
    return BusStatus::kOk;
  }

  void spi(const uint8_t* tx, uint8_t* rx, size_t n) override {
    if (n == 0) return;
    const bool read = (tx[0] & rules_.spi_read_bit) != 0;
    const bool inc = rules_.always_increment || (tx[0] & rules_.spi_increment_bit) != 0;
    const uint8_t reg = static_cast<uint8_t>(tx[0] & ~(rules_.spi_read_bit | rules_.spi_increment_bit));
    rx[0] = 0x00;  // the chip drives nothing useful while the address goes in
    if (read)
      access(reg, inc, nullptr, 0, rx + 1, n - 1);
    else
      access(reg, inc, tx + 1, n - 1, nullptr, 0);
  }

  std::array<uint8_t, 256> regs{};
  std::vector<std::pair<uint8_t, uint8_t>> writes;  // every register write, in order
  int multi_byte_writes = 0;                        // write transactions of more than one data byte

 protected:
  // The register after `reg` in a burst.
  virtual uint8_t next(uint8_t reg) const { return static_cast<uint8_t>(reg + 1); }
  // What reading `reg` answers (and what reading it does to the chip).
  virtual uint8_t read_register(uint8_t reg) { return regs[reg]; }
  // What a write of `value` to `reg` does; the default stores it.
  virtual void write_register(uint8_t reg, uint8_t value) { regs[reg] = value; }
  // Where the second data byte of a write transaction goes.
  virtual bool write_increments(bool inc) const { return inc; }

 private:
  void access(uint8_t reg, bool inc, const uint8_t* w, size_t wn, uint8_t* r, size_t rn) {
    if (wn > 1) ++multi_byte_writes;
    uint8_t at = reg;
    for (size_t i = 0; i < wn; ++i) {
      writes.emplace_back(at, w[i]);
      write_register(at, w[i]);
      if (write_increments(inc)) at = next(at);
    }
    at = reg;
    for (size_t i = 0; i < rn; ++i) {
      r[i] = read_register(at);
      if (inc) at = next(at);
    }
  }

  Rules rules_;
};

}  // namespace nlsoft::fw::drivers::fake
