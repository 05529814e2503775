#pragma once
// The system half of a Cortex-M4 vector table, shared by the ports; each
// port's vectors.cpp appends its interrupt lines. The system handlers are
// weak aliases of Default_Handler (reset.cpp), so a driver that needs one
// (systick.cpp) overrides it and the rest trap.
#include <cstdint>

extern "C" {
extern uint32_t __stack_top__;
void Reset_Handler();
void Default_Handler();
void NMI_Handler();
void HardFault_Handler();
void MemManage_Handler();
void BusFault_Handler();
void UsageFault_Handler();
void SVC_Handler();
void DebugMon_Handler();
void PendSV_Handler();
void SysTick_Handler();
}

namespace nlsoft::fw::cortex_m {

using Vector = void (*)();

template <int kIrqCount>
struct VectorTable {
  uint32_t* initial_sp;
  Vector system[15];
  Vector irq[kIrqCount];
};

#define NLSOFT_CORTEX_M_SYSTEM_VECTORS                                                                    \
  {Reset_Handler, NMI_Handler,  HardFault_Handler, MemManage_Handler, BusFault_Handler, UsageFault_Handler, \
   nullptr,       nullptr,      nullptr,           nullptr,           SVC_Handler,      DebugMon_Handler,   \
   nullptr,       PendSV_Handler, SysTick_Handler}

}  // namespace nlsoft::fw::cortex_m
