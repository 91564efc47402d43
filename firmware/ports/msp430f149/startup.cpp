/// \file
/// \brief MSP430F149 start-up: the reset handler (watchdog, stack pointer, .data, .bss, the
/// stack's paint, firmware_main) and the interrupt vector table's reset entry. The other vectors
/// are filled by the linker script from the ISRs main.cpp defines (link.ld).
///
/// No static constructors: every object of the image is constant-initialised (the device object
/// is `constinit`), and link.ld refuses an image with a non-empty .init_array. A flasher that
/// programs only PROGBITS sections (Debian's mspdebug 0.22 skips .init_array, whose type is
/// INIT_ARRAY) would leave such a table erased, and the start-up would call 0xFFFF.
#include <stdint.h>

extern "C" {
// Arrays of unknown bound: the linker script says where they start and end.
extern uint16_t __data_start[], __data_end[], __data_load[], __bss_start[], __bss_end[];
extern uint16_t __stack_paint_start[];
void firmware_main();
void reset_handler();
void continue_reset();
}

// First the watchdog: after a reset it runs from SMCLK (the DCO, ~0.8 MHz) and would reset the
// part after 32 768 cycles (MSP430x1xx Family User's Guide, SLAU049, §10.2: WDTCTL = 0 after
// PUC); clearing .bss alone takes ~10 000 of them. Then the stack pointer: nothing may use the
// stack before it is set. WDTCTL = WDTPW | WDTHOLD (0x5A80) at 0x0120.
extern "C" __attribute__((naked)) void reset_handler() {
  __asm__ volatile("mov #0x5a80, &0x0120\n mov #__stack, r1\n br #continue_reset");
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
  // Paint the free stack (below this frame, with a margin) so that its deepest use can be found
  // later (main.cpp stack_free).
  uintptr_t sp = 0;
  __asm__ volatile("mov r1, %0" : "=r"(sp));
  for (uint16_t* p = __stack_paint_start; reinterpret_cast<uintptr_t>(p) + 16 < sp; ++p)
    *p = 0xA55A;
  firmware_main();
  for (;;) {
  }
}

// A spurious interrupt (a vector main.cpp does not use): return from it.
extern "C" __attribute__((interrupt(0))) void isr_unused() {}
