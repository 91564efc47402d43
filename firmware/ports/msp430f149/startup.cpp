/// \file
/// \brief MSP430F149 start-up: the reset handler (stack pointer, .data, .bss, static
/// constructors, firmware_main) and the interrupt vector table's reset entry. The other vectors are
/// filled by the linker script from the ISRs main.cpp defines (link.ld).
#include <stdint.h>

extern "C" {
// Arrays of unknown bound: the linker script says where they start and end.
extern uint16_t __data_start[], __data_end[], __data_load[], __bss_start[], __bss_end[];
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();
void firmware_main();
void reset_handler();
void continue_reset();
}

// The stack pointer first: nothing may use the stack before it is set.
extern "C" __attribute__((naked)) void reset_handler() {
  __asm__ volatile("mov #__stack, r1\n br #continue_reset");
}

extern "C" void continue_reset() {
  // Word counts from the addresses: the linker's symbols are not one C++ object.
  const uintptr_t data_words =
      (reinterpret_cast<uintptr_t>(__data_end) - reinterpret_cast<uintptr_t>(__data_start)) /
      sizeof(uint16_t);
  const uintptr_t bss_words =
      (reinterpret_cast<uintptr_t>(__bss_end) - reinterpret_cast<uintptr_t>(__bss_start)) /
      sizeof(uint16_t);
  for (uintptr_t i = 0; i < data_words; ++i) __data_start[i] = __data_load[i];
  for (uintptr_t i = 0; i < bss_words; ++i) __bss_start[i] = 0;
  for (void (**f)() = __init_array_start; f < __init_array_end; ++f) (*f)();
  firmware_main();
  for (;;) {
  }
}

// A spurious interrupt (a vector main.cpp does not use): return from it.
extern "C" __attribute__((interrupt(0))) void isr_unused() {}
