#pragma once
// Pin set-up: alternate function (USART, timer, bus), analogue (ADC) or
// output (chip select, a bus being recovered) mode.
// The GPIO port's clock must be on (RCC AHB1ENR) before these.
#include <cstdint>

#include "firmware/ports/stm32f4/regs.hpp"

namespace nlsoft::fw::stm32f4 {

// RCC AHB1ENR bit of a GPIO port: A = 0, B = 1, ...
inline uint32_t gpio_clock_bit(uint32_t port) { return 1u << ((port - kGpioA) / 0x400u); }

inline void gpio_alternate(Pin p, uint32_t af) {
  const uint32_t shift = 2u * p.number;
  reg(p.port + 0x00) = (reg(p.port + 0x00) & ~(3u << shift)) | (2u << shift);   // MODER: alternate
  reg(p.port + 0x08) = (reg(p.port + 0x08) | (2u << shift));                     // OSPEEDR: fast
  const uint32_t afr = p.port + (p.number < 8 ? 0x20u : 0x24u), at = 4u * (p.number % 8u);
  reg(afr) = (reg(afr) & ~(0xFu << at)) | (af << at);
}

// Open-drain (I²C): the pin only pulls low; the bus's pull-ups raise it.
inline void gpio_open_drain(Pin p) { reg(p.port + 0x04) = reg(p.port + 0x04) | (1u << p.number); }

inline void gpio_output(Pin p) {
  const uint32_t shift = 2u * p.number;
  reg(p.port + 0x00) = (reg(p.port + 0x00) & ~(3u << shift)) | (1u << shift);  // MODER: output
  reg(p.port + 0x08) = (reg(p.port + 0x08) | (2u << shift));                    // OSPEEDR: fast
}

// BSRR: set and reset in one write, no read-modify-write to race an interrupt.
inline void gpio_write(Pin p, bool high) { reg(p.port + 0x18) = high ? (1u << p.number) : (1u << (p.number + 16u)); }
inline bool gpio_read(Pin p) { return (reg(p.port + 0x10) >> p.number) & 1u; }

inline void gpio_analogue(Pin p) {
  const uint32_t shift = 2u * p.number;
  reg(p.port + 0x00) = reg(p.port + 0x00) | (3u << shift);  // MODER: analogue
  reg(p.port + 0x0C) = reg(p.port + 0x0C) & ~(3u << shift);  // PUPDR: none
}

}  // namespace nlsoft::fw::stm32f4
