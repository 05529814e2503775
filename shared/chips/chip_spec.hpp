#pragma once
// What a sensor chip is, as data: its bus, its identity, its channels and
// the ranges and rates it can be set to. The rig loader checks a rig file's
// [[device]] against it (an unknown chip, range or rate is an error at the
// file's line) and the firmware's driver takes its register values from it,
// so the file and the image cannot disagree about what a chip can do.
#include <cstdint>

namespace nlsoft::chips {

// One setting a chip offers: the value a rig file writes (gauss, Hz, ...)
// and the register bits that select it.
struct Setting {
  float value;
  uint8_t bits;
};

struct ChipSpec {
  const char* name;           // as a rig file writes it: chip = "lis3mdl"
  bool on_i2c, on_spi;        // the buses it can be wired to
  uint8_t default_address;    // I²C: the 7-bit address with its address pin as shipped boards strap it
  bool has_id;                // an identity register to check at boot (an ADC may have none)
  uint8_t id_register;        // ... and the value the chip answers
  uint8_t id_value;
  const char* const* channel_names;  // x, y, z / pressure, temperature / ch0..
  const char* const* channel_units;  // "uT", "Pa", "degC", "V"
  int channel_count;
  const char* range_unit;            // what `range` is written in ("gauss"); nullptr: no range key
  const Setting* ranges;
  int range_count;
  const Setting* rates;              // data rates in Hz
  int rate_count;
  uint32_t max_clock_hz;             // the fastest clock: SPI's for a chip on_spi, else I²C's; a servo's highest baud
  uint8_t spi_mode;                  // SPI: CPOL << 1 | CPHA
  // A smart servo on a single-wire half-duplex serial bus (Dynamixel):
  // the packet protocol it speaks (1 or 2; 0 for a chip that is no servo),
  // the model number it answers with (its identity), the baud it leaves the
  // factory at, and the highest goal position its control table takes.
  uint8_t servo_protocol = 0;
  uint16_t model_number = 0;
  uint32_t default_baud = 0;
  uint32_t goal_max = 0;
};

constexpr bool on_serial(const ChipSpec& c) { return c.servo_protocol != 0; }

// Where `s` is in `list` (matched on value and bits), or -1: a driver
// takes its per-setting constants (a sensitivity) from the same index.
inline int setting_index(const Setting* list, int count, Setting s) {
  for (int i = 0; i < count; ++i)
    if (list[i].value == s.value && list[i].bits == s.bits) return i;
  return -1;
}

}  // namespace nlsoft::chips
