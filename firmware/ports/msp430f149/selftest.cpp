/// \file
/// \brief The MSP430 self-test image (selftest.hpp): the firmware's arithmetic and the runtime
/// helpers, run on the MSP430 instruction simulator from a mailbox the host test fills. Built
/// with the shipped image's compiler, flags, start-up and runtime.cpp; only firmware_main differs.
#include <stdint.h>

#include "firmware/ports/msp430f149/selftest.hpp"

namespace {

using namespace gyroflip;
using fw::selftest::op;

// Operands come from memory the compiler cannot see through (volatile): every operator of
// selftest::compute is a real call of the runtime helper, never a folded constant.
uint64_t load(const volatile uint8_t* p, uint8_t bytes) {
  uint64_t v = 0;
  for (uint8_t i = bytes; i > 0; --i) v = (v << 8) | p[i - 1];
  return v;
}
void store(volatile uint8_t* p, uint64_t v) {
  for (uint8_t i = 0; i < 8; ++i) {
    p[i] = static_cast<uint8_t>(v & 0xFFu);
    v >>= 8;
  }
}

fw::calibrator cal;  // its state runs from one record to the next

}  // namespace

extern "C" {

// The host test's breakpoint: the mailbox is done.
__attribute__((noinline)) void selftest_done() {
  __asm__ volatile("nop");
}

void firmware_main() {
  namespace st = fw::selftest;
  const auto* in = reinterpret_cast<const volatile uint8_t*>(st::in_addr);
  auto* out = reinterpret_cast<volatile uint8_t*>(st::out_addr);
  const auto count = static_cast<uint16_t>(load(in, 2));
  for (uint16_t i = 0; i < count && i < st::max_records; ++i) {
    const volatile uint8_t* rec = &in[2 + uint32_t{st::in_record_bytes} * i];
    const fw::selftest::results r =
        fw::selftest::compute(static_cast<op>(rec[0]), load(rec + 2, 8), load(rec + 10, 8), cal);
    store(out + uint32_t{st::out_record_bytes} * i, r.r0);
    store(out + uint32_t{st::out_record_bytes} * i + 8, r.r1);
  }
  selftest_done();
}

// The vector table of link.ld names the shipped image's interrupt handlers.
__attribute__((interrupt(0))) void isr_timer_a1() {}
__attribute__((interrupt(0))) void isr_timer_b1() {}
__attribute__((interrupt(0))) void isr_usart0_rx() {}
__attribute__((interrupt(0))) void isr_usart0_tx() {}
__attribute__((interrupt(0))) void isr_nmi() {}

}  // extern "C"
