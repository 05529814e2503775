// The AN386 vector table: the CMSDK peripherals raise IRQ 0..31; only UART0
// receive is used (its handler is in cmsdk_uart.cpp, linked into every image).
#include "firmware/ports/cortex-m/vectors.hpp"

extern "C" void Uart0Rx_Handler();

__attribute__((section(".isr_vector"), used)) const nlsoft::fw::cortex_m::VectorTable<32> g_vectors = {
    &__stack_top__,
    NLSOFT_CORTEX_M_SYSTEM_VECTORS,
    {Uart0Rx_Handler,  // IRQ 0: UART0 receive
     Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
     Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
     Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
     Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
     Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler, Default_Handler,
     Default_Handler}};
