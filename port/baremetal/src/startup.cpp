// Minimal Cortex-M startup: the vector table, .data copied from flash, .bss zeroed, static
// constructors run, then firmware_main() (C++ may not call main()). Every exception without a
// handler parks in Default_Handler.
#include <cstddef>
#include <cstdint>

extern "C" {
// From the linker script.
extern std::uint32_t __stack_top;
extern std::uint32_t __data_start, __data_end, __data_load, __bss_start, __bss_end;
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();

void firmware_main();
void Reset_Handler();
void Default_Handler();
void NMI_Handler() __attribute__((weak, alias("Default_Handler")));
void HardFault_Handler() __attribute__((weak, alias("Default_Handler")));
void SVC_Handler() __attribute__((weak, alias("Default_Handler")));
void PendSV_Handler() __attribute__((weak, alias("Default_Handler")));
void SysTick_Handler() __attribute__((weak, alias("Default_Handler")));
void CAN0_IRQHandler() __attribute__((weak, alias("Default_Handler")));
}

// One word of the vector table: the initial stack pointer, a handler or reserved (0).
union VectorEntry {
  constexpr VectorEntry(void (*function)()) : handler(function) {}
  constexpr VectorEntry(std::uint32_t* stack_top) : stack(stack_top) {}
  constexpr VectorEntry(std::nullptr_t) : handler(nullptr) {}
  void (*handler)();
  std::uint32_t* stack;
};

// ARMv6-M/ARMv7-M: 16 system entries, then the interrupts (IRQ 0: the CAN receive interrupt).
__attribute__((section(".vectors"), used)) const VectorEntry vector_table[17] = {
    &__stack_top,    Reset_Handler,   NMI_Handler,     HardFault_Handler, Default_Handler,
    Default_Handler, Default_Handler, nullptr,         nullptr,           nullptr,
    nullptr,         SVC_Handler,     Default_Handler, nullptr,           PendSV_Handler,
    SysTick_Handler, CAN0_IRQHandler};

extern "C" void Reset_Handler() {
#if defined(__ARM_FP)
  // Cortex-M4F: full access to the FPU (CPACR CP10, CP11) before any floating-point instruction.
  *reinterpret_cast<volatile std::uint32_t*>(0xE000ED88u) |= 0xFu << 20;
  __asm volatile("dsb\n\tisb" ::: "memory");
#endif
  for (std::uint32_t *from = &__data_load, *to = &__data_start; to < &__data_end;) *to++ = *from++;
  for (std::uint32_t* to = &__bss_start; to < &__bss_end;) *to++ = 0;
  for (void (**init)() = __init_array_start; init < __init_array_end; ++init) (*init)();
  firmware_main();
  for (;;) {
  }
}

extern "C" void Default_Handler() {
  for (;;) {
  }
}
