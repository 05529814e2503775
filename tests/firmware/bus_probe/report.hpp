#pragma once
// The bus probe images' answer: text lines over the board's link, written
// only when the host asks (a byte 'r'), since what an image sends before the
// host opens the pty is lost. The first line repeats the request's tag; a line is a name, the BusStatus as a number
// (0 ok, 1 nack, 2 timeout, 3 bus error) and values: bytes in hex, counts
// and raw readings in decimal. The last line is "end".
#include <cstddef>
#include <cstdint>
#include <initializer_list>

#include "firmware/drivers/bus.hpp"
#include "firmware/ports/cortex-m/board.hpp"
#include "firmware/ports/cortex-m/systick.hpp"

namespace nlsoft::test::probe {

class Report {
 public:
  // Values after the first are separated by a space (lines stay shorter than the buffer).
  Report& word(const char* s) {
    if (at_ > 0) put(' ');
    while (*s) put(*s++);
    return *this;
  }
  Report& status(fw::drivers::BusStatus s) { return number(int32_t(s)); }
  Report& number(int32_t v) {
    char digits[12];
    int n = 0;
    uint32_t u = v < 0 ? uint32_t(-(v + 1)) + 1u : uint32_t(v);
    do digits[n++] = char('0' + u % 10u);
    while ((u /= 10u) != 0);
    if (at_ > 0) put(' ');
    if (v < 0) put('-');
    while (n > 0) put(digits[--n]);
    return *this;
  }
  Report& hex(uint8_t b) {
    static const char kDigits[] = "0123456789abcdef";
    if (at_ > 0) put(' ');
    put(kDigits[b >> 4]);
    put(kDigits[b & 15u]);
    return *this;
  }
  Report& bytes(const uint8_t* b, size_t n) {
    for (size_t i = 0; i < n; ++i) hex(b[i]);
    return *this;
  }
  void end_line() {
    put('\n');
    flush();
  }

 private:
  void put(char c) {
    if (at_ == sizeof line_) flush();
    line_[at_++] = uint8_t(c);
  }
  void flush() {
    size_t sent = 0;
    // The transmitter drains at the link's rate; bounded all the same.
    for (uint32_t tries = 0; sent < at_ && tries < 1000000u; ++tries)
      sent += fw::board::serial_write(line_ + sent, at_ - sent);
    at_ = 0;
  }
  uint8_t line_[96];
  size_t at_ = 0;
};

// Waits for the host's request, 'r' and a tag byte, and returns the tag
// (anything before the 'r' is dropped). The report repeats it, so the host
// tells the answer to this request from one to a request it repeated
// earlier while the image was still busy or booting.
inline char wait_for_request() {
  uint8_t b = 0;
  for (;;) {
    fw::board::watchdog_kick();
    if (fw::board::serial_read(&b, 1) == 1 && b == 'r') break;
  }
  // The tag is written with the 'r'; bounded all the same.
  for (uint32_t tries = 0; tries < 10000000u; ++tries) {
    fw::board::watchdog_kick();
    if (fw::board::serial_read(&b, 1) == 1) return char(b);
  }
  return '?';
}

// QEMU's max1111 on `bus`: a conversion of input 0 and of input 1 (START,
// single-ended, unipolar, powered up; lines adc_00 and adc_40, by the SEL
// bits), then a 7-byte transfer timed in core clocks (spi_xfer7 with the
// bit rate the master chose, spi_xfer7_ticks).
inline void probe_adc(fw::drivers::SpiBus& bus, const fw::drivers::SpiTarget& adc, uint32_t bit_rate_hz, Report& out) {
  for (uint8_t select : {uint8_t(0x00), uint8_t(0x40)}) {
    const uint8_t tx[3] = {uint8_t(0x8F | select), 0, 0};
    uint8_t rx[3] = {};
    out.word(select ? "adc_40" : "adc_00").status(bus.transfer(adc, tx, rx, 3)).bytes(rx, 3).end_line();
  }
  const uint8_t seven[7] = {0x8F, 0, 0, 0, 0, 0, 0};
  uint8_t back[7] = {};
  const uint32_t t0 = fw::board::ticks();
  const fw::drivers::BusStatus s = bus.transfer(adc, seven, back, 7);
  const uint32_t ticks = fw::board::ticks() - t0;
  out.word("spi_xfer7").status(s).number(int32_t(bit_rate_hz)).end_line();
  out.word("spi_xfer7_ticks").number(int32_t(ticks)).end_line();
}

// A probe image's main: the board and SysTick (the tick the masters time
// with), then a report per request, closed by the core clock and "end".
[[noreturn]] inline void serve(void (*probe)(Report&)) {
  fw::board::start(115200);
  fw::cortex_m::systick_start(fw::board::core_clock_hz() / 1000u);
  Report out;
  for (;;) {
    const char tag[2] = {wait_for_request(), '\0'};
    out.word("tag").word(tag).end_line();
    probe(out);
    out.word("core_hz").number(int32_t(fw::board::core_clock_hz())).end_line();
    out.word("end").end_line();
  }
}

}  // namespace nlsoft::test::probe
