#pragma once
// Pin set-up: alternate function (USART, timer) or analogue (ADC) mode.
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

inline void gpio_analogue(Pin p) {
  const uint32_t shift = 2u * p.number;
  reg(p.port + 0x00) = reg(p.port + 0x00) | (3u << shift);  // MODER: analogue
  reg(p.port + 0x0C) = reg(p.port + 0x0C) & ~(3u << shift);  // PUPDR: none
}

}  // namespace nlsoft::fw::stm32f4
