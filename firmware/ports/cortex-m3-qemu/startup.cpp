/// \file
/// \brief Cortex-M3 start-up for QEMU's mps2-an385: vector table, copy .data, zero .bss, run
/// the static constructors, main(), then leave QEMU through ARM semihosting (SYS_EXIT with
/// ADP_Stopped_ApplicationExit: exit code 0; any fault: exit code 1).
#include <stdint.h>

extern "C" {
// Arrays of unknown bound: the linker script says where they start and end.
extern uint32_t __data_start[], __data_end[], __data_load[], __bss_start[], __bss_end[], _estack;
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();
int main();
void Reset_Handler();
void Fault_Handler();
}

namespace {
[[noreturn]] void semihost_exit(uint32_t reason) {
  // SYS_EXIT (0x18) with the reason code in r1.
  register uint32_t r0 __asm__("r0") = 0x18;
  register uint32_t r1 __asm__("r1") = reason;
  __asm__ volatile("bkpt 0xAB" : : "r"(r0), "r"(r1) : "memory");
  for (;;) {
  }
}
}  // namespace

extern "C" void Reset_Handler() {
  // Word counts from the addresses: the linker's symbols are not one C++ object.
  const uintptr_t data_words =
      (reinterpret_cast<uintptr_t>(__data_end) - reinterpret_cast<uintptr_t>(__data_start)) /
      sizeof(uint32_t);
  const uintptr_t bss_words =
      (reinterpret_cast<uintptr_t>(__bss_end) - reinterpret_cast<uintptr_t>(__bss_start)) /
      sizeof(uint32_t);
  for (uintptr_t i = 0; i < data_words; ++i) __data_start[i] = __data_load[i];
  for (uintptr_t i = 0; i < bss_words; ++i) __bss_start[i] = 0;
  for (void (**f)() = __init_array_start; f < __init_array_end; ++f) (*f)();
  main();
  semihost_exit(0x20026);  // ADP_Stopped_ApplicationExit
}

extern "C" void Fault_Handler() {
  semihost_exit(0x20023);
}  // ADP_Stopped_InternalError

using handler = void (*)();
__attribute__((section(".isr_vector"), used))
const handler vector_table[16] = {reinterpret_cast<handler>(&_estack),  // initial stack pointer
                                  Reset_Handler,
                                  Fault_Handler,
                                  Fault_Handler,
                                  Fault_Handler,
                                  Fault_Handler,
                                  Fault_Handler,
                                  nullptr,
                                  nullptr,
                                  nullptr,
                                  nullptr,
                                  Fault_Handler,
                                  Fault_Handler,
                                  nullptr,
                                  Fault_Handler,
                                  Fault_Handler};
