// Reset for any Cortex-M image: the handler that makes C++ usable (the FPU on where
// there is one, .data copied, .bss zeroed, static constructors run) and the traps a
// bare-metal C++ image needs. Each port's vectors.cpp places them in its
// vector table, with the interrupts its peripherals raise.
#include <cstdint>
#include <cstring>

extern "C" {
extern uint32_t __data_start__, __data_end__, __data_load__, __bss_start__, __bss_end__, __stack_top__;
void __libc_init_array();
int main();

void Reset_Handler();
void Default_Handler();
// Weak so that the drivers that need them (systick.cpp) override them and
// the rest trap in Default_Handler.
void NMI_Handler() __attribute__((weak, alias("Default_Handler")));
void HardFault_Handler() __attribute__((weak, alias("Default_Handler")));
void MemManage_Handler() __attribute__((weak, alias("Default_Handler")));
void BusFault_Handler() __attribute__((weak, alias("Default_Handler")));
void UsageFault_Handler() __attribute__((weak, alias("Default_Handler")));
void SVC_Handler() __attribute__((weak, alias("Default_Handler")));
void DebugMon_Handler() __attribute__((weak, alias("Default_Handler")));
void PendSV_Handler() __attribute__((weak, alias("Default_Handler")));
void SysTick_Handler() __attribute__((weak, alias("Default_Handler")));
}

extern "C" {

// Kept out of Reset_Handler so no floating-point instruction can be
// scheduled before CPACR grants the FPU (it would fault with NOCP).
__attribute__((noinline)) static void init_runtime() {
  std::memcpy(&__data_start__, &__data_load__,
              size_t(reinterpret_cast<uintptr_t>(&__data_end__) - reinterpret_cast<uintptr_t>(&__data_start__)));
  std::memset(&__bss_start__, 0,
              size_t(reinterpret_cast<uintptr_t>(&__bss_end__) - reinterpret_cast<uintptr_t>(&__bss_start__)));
  __libc_init_array();
}

void Reset_Handler() {
#if defined(__ARM_FP)  // a core without an FPU (the M3) has no CPACR to set
  volatile uint32_t& cpacr = *reinterpret_cast<volatile uint32_t*>(0xE000ED88u);
  cpacr = cpacr | (0xFu << 20);  // CP10 and CP11 full access: the FPU
  __asm volatile("dsb\n\tisb" ::: "memory");
#endif
  init_runtime();
  main();
  for (;;) {
  }
}

// A fault or an unexpected interrupt: stop here, where a debugger finds it;
// the console sees the heartbeat stop.
void Default_Handler() {
  for (;;) {
  }
}

// -nostartfiles drops crti.o; __libc_init_array still calls _init.
void _init() {}

// A pure virtual call is a bug; with -fno-exceptions there is nothing to
// unwind to, and libstdc++'s version would drag in its verbose terminate.
void __cxa_pure_virtual() {
  for (;;) {
  }
}

}  // extern "C"
