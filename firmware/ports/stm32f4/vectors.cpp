// The STM32F4 vector table: 97 interrupt lines on the F446 (fewer on the
// F401/F411, whose extra entries are never raised). Only USART2 (IRQ 38) is
// used; its handler is in usart2.cpp, linked into every image.
#include "firmware/ports/cortex-m/vectors.hpp"

extern "C" void USART2_IRQHandler();

namespace {

using nlsoft::fw::cortex_m::VectorTable;
constexpr int kIrqCount = 97;
constexpr int kUsart2Irq = 38;

constexpr VectorTable<kIrqCount> make_table() {
  VectorTable<kIrqCount> t{&__stack_top__, NLSOFT_CORTEX_M_SYSTEM_VECTORS, {}};
  for (auto& v : t.irq) v = Default_Handler;
  t.irq[kUsart2Irq] = USART2_IRQHandler;
  return t;
}

}  // namespace

__attribute__((section(".isr_vector"), used)) const VectorTable<kIrqCount> g_vectors = make_table();
