/// \file
/// \brief The run-time helpers the MSP430 link needs (Debian has clang for msp430 but no
/// runtime library, STACK.md §6): memory copies and the integer arithmetic of the MSP430 EABI
/// (TI SLAA534, "MSP430 Embedded Application Binary Interface", section 6.3 helper functions).
/// Plain shift-and-add, shift-and-subtract loops: small, exact, no hardware multiplier needed.
///
/// Calling conventions (SLAA534 §3 and §6.3; what clang 14 emits, docs/FIRMWARE.md): the 16- and
/// 32-bit helpers and the 64-bit shifts follow the ordinary convention (arguments in R12..R15,
/// then the stack). The 64-bit multiply, divide and remainder helpers do not: their first operand
/// is in R8..R11 and the second in R12..R15 (least significant word first), the result in
/// R12..R15. A C++ definition of those would read its second operand from the stack, where the
/// caller never put it; they are therefore small assembly entries that move the operands into
/// the ordinary convention and call the C++ implementation. Every helper is checked bit for bit
/// against the host on the MSP430 instruction simulator (tests/firmware/test_msp430_sim.cpp).
#include <stddef.h>
#include <stdint.h>

namespace {

template <class U>
U mul(U a, U b) {
  U r = 0;
  while (b != 0) {
    if ((b & 1u) != 0) r = static_cast<U>(r + a);
    a = static_cast<U>(a << 1);
    b = static_cast<U>(b >> 1);
  }
  return r;
}

// Restoring division, one bit per turn. Shifts are by the constant 1 only: a variable shift
// would itself call a helper below.
template <class U>
U udivmod(U n, U d, U* rem) {
  if (d == 0) {  // undefined in C; return all ones rather than trap
    *rem = n;
    return static_cast<U>(~U{0});
  }
  constexpr int bits = static_cast<int>(sizeof(U) * 8);
  constexpr U top = static_cast<U>(U{1} << (bits - 1));
  U q = 0;
  U r = 0;
  for (int i = 0; i < bits; ++i) {
    const bool carry = (r & top) != 0;
    r = static_cast<U>((r << 1) | ((n & top) != 0 ? 1u : 0u));
    n = static_cast<U>(n << 1);
    q = static_cast<U>(q << 1);
    if (carry || r >= d) {
      r = static_cast<U>(r - d);
      q = static_cast<U>(q | 1u);
    }
  }
  *rem = r;
  return q;
}

template <class U>
U shift_left(U v, int n) {
  for (; n > 0; --n) v = static_cast<U>(v << 1);
  return v;
}
template <class U>
U shift_right(U v, int n) {
  for (; n > 0; --n) v = static_cast<U>(v >> 1);
  return v;
}

template <class S, class U>
S sdiv(S n, S d, bool want_rem) {
  const bool nn = n < 0;
  const bool nd = d < 0;
  const U un = nn ? static_cast<U>(U{0} - static_cast<U>(n)) : static_cast<U>(n);
  const U ud = nd ? static_cast<U>(U{0} - static_cast<U>(d)) : static_cast<U>(d);
  U r = 0;
  const U q = udivmod<U>(un, ud, &r);
  if (want_rem) return nn ? static_cast<S>(U{0} - r) : static_cast<S>(r);
  return (nn != nd) ? static_cast<S>(U{0} - q) : static_cast<S>(q);
}

}  // namespace

extern "C" {

void* memcpy(void* dst, const void* src, size_t n) {
  auto* d = static_cast<uint8_t*>(dst);
  const auto* s = static_cast<const uint8_t*>(src);
  for (size_t i = 0; i < n; ++i) d[i] = s[i];
  return dst;
}
void* memmove(void* dst, const void* src, size_t n) {
  auto* d = static_cast<uint8_t*>(dst);
  const auto* s = static_cast<const uint8_t*>(src);
  if (d < s) {
    for (size_t i = 0; i < n; ++i) d[i] = s[i];
  } else {
    for (size_t i = n; i > 0; --i) d[i - 1] = s[i - 1];
  }
  return dst;
}
void* memset(void* dst, int v, size_t n) {
  auto* d = static_cast<uint8_t*>(dst);
  for (size_t i = 0; i < n; ++i) d[i] = static_cast<uint8_t>(v);
  return dst;
}

int16_t __mspabi_mpyi(int16_t a, int16_t b) {
  return static_cast<int16_t>(mul<uint16_t>(static_cast<uint16_t>(a), static_cast<uint16_t>(b)));
}
int32_t __mspabi_mpyl(int32_t a, int32_t b) {
  return static_cast<int32_t>(mul<uint32_t>(static_cast<uint32_t>(a), static_cast<uint32_t>(b)));
}
int64_t gyroflip_rt_mpyll(int64_t a, int64_t b) {
  return static_cast<int64_t>(mul<uint64_t>(static_cast<uint64_t>(a), static_cast<uint64_t>(b)));
}

uint16_t __mspabi_divu(uint16_t n, uint16_t d) {
  uint16_t r;
  return udivmod<uint16_t>(n, d, &r);
}
uint16_t __mspabi_remu(uint16_t n, uint16_t d) {
  uint16_t r;
  udivmod<uint16_t>(n, d, &r);
  return r;
}
int16_t __mspabi_divi(int16_t n, int16_t d) {
  return sdiv<int16_t, uint16_t>(n, d, false);
}
int16_t __mspabi_remi(int16_t n, int16_t d) {
  return sdiv<int16_t, uint16_t>(n, d, true);
}
uint32_t __mspabi_divul(uint32_t n, uint32_t d) {
  uint32_t r;
  return udivmod<uint32_t>(n, d, &r);
}
uint32_t __mspabi_remul(uint32_t n, uint32_t d) {
  uint32_t r;
  udivmod<uint32_t>(n, d, &r);
  return r;
}
int32_t __mspabi_divli(int32_t n, int32_t d) {
  return sdiv<int32_t, uint32_t>(n, d, false);
}
int32_t __mspabi_remli(int32_t n, int32_t d) {
  return sdiv<int32_t, uint32_t>(n, d, true);
}
uint64_t gyroflip_rt_divull(uint64_t n, uint64_t d) {
  uint64_t r;
  return udivmod<uint64_t>(n, d, &r);
}
uint64_t gyroflip_rt_remull(uint64_t n, uint64_t d) {
  uint64_t r;
  udivmod<uint64_t>(n, d, &r);
  return r;
}
int64_t gyroflip_rt_divlli(int64_t n, int64_t d) {
  return sdiv<int64_t, uint64_t>(n, d, false);
}
int64_t gyroflip_rt_remlli(int64_t n, int64_t d) {
  return sdiv<int64_t, uint64_t>(n, d, true);
}

uint32_t __mspabi_slll(uint32_t v, int16_t n) {
  return shift_left<uint32_t>(v, n);
}
uint32_t __mspabi_srll(uint32_t v, int16_t n) {
  return shift_right<uint32_t>(v, n);
}
int32_t __mspabi_sral(int32_t v, int16_t n) {
  for (; n > 0; --n) v = v / 2 - ((v < 0 && (v & 1) != 0) ? 1 : 0);  // floor, as >> does
  return v;
}
uint64_t __ashldi3(uint64_t v, int n) {
  return shift_left<uint64_t>(v, n);
}
uint64_t __lshrdi3(uint64_t v, int n) {
  return shift_right<uint64_t>(v, n);
}
int64_t __ashrdi3(int64_t v, int n) {
  // Arithmetic: the sign bit is copied in; the shift itself is done unsigned (defined in C++).
  const uint64_t sign = v < 0 ? ~uint64_t{0} : 0;
  uint64_t u = static_cast<uint64_t>(v);
  for (; n > 0; --n) u = (u >> 1) | (sign & (uint64_t{1} << 63));
  return static_cast<int64_t>(u);
}

}  // extern "C"

// The special-convention entries (see the file comment): push the second operand (R12..R15) so
// that it lies on the stack as the ordinary convention's second 64-bit argument, move the first
// (R8..R11) to R12..R15, call the implementation, drop the pushed operand. R8..R10 are untouched
// (the implementation preserves them, as the ordinary convention requires); R11 may change, as
// for any call.
#define GYROFLIP_MSPABI_64(name, impl)                                     \
  __asm__(".section .text." #name                                          \
          ",\"ax\",@progbits\n"                                            \
          ".global " #name                                                 \
          "\n"                                                             \
          ".type " #name ",@function\n" #name                              \
          ":\n"                                                            \
          "  push r15\n  push r14\n  push r13\n  push r12\n"               \
          "  mov r8, r12\n  mov r9, r13\n  mov r10, r14\n  mov r11, r15\n" \
          "  call #" #impl                                                 \
          "\n"                                                             \
          "  add #8, r1\n"                                                 \
          "  ret\n"                                                        \
          ".size " #name ", .-" #name "\n")
GYROFLIP_MSPABI_64(__mspabi_mpyll, gyroflip_rt_mpyll);
GYROFLIP_MSPABI_64(__mspabi_divull, gyroflip_rt_divull);
GYROFLIP_MSPABI_64(__mspabi_remull, gyroflip_rt_remull);
GYROFLIP_MSPABI_64(__mspabi_divlli, gyroflip_rt_divlli);
GYROFLIP_MSPABI_64(__mspabi_remlli, gyroflip_rt_remlli);
