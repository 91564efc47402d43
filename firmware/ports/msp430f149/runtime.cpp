/// \file
/// \brief The run-time helpers the MSP430 link needs (Debian has clang for msp430 but no
/// runtime library, STACK.md §6): memory copies and the integer arithmetic of the MSP430 EABI
/// (TI SLAA534, "MSP430 Embedded Application Binary Interface", section 6.3 helper functions).
/// Products on the F149's hardware multiplier (16 x 16 partial products), divisions as restoring
/// shift-and-subtract loops in assembly for 16, 32 and 64 bits: exact, and fast enough for a
/// step's interval and CONFIGURE's link budget inside one main-loop pass (docs/FIRMWARE.md).
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

// The MSP430F149's 16 x 16 hardware multiplier (SLAU049 §7; registers at 0x130): MPY takes the
// first operand, OP2 the second and starts the product, RESHI:RESLO hold it. Interrupts are off
// around each use (a handler that multiplied would overwrite the operands). Every product is
// built from 16 x 16 -> 32 partial products, the schoolbook way.
volatile uint16_t& hw(uint16_t addr) {
  return *reinterpret_cast<volatile uint16_t*>(addr);
}
constexpr uint16_t hw_mpy = 0x130, hw_op2 = 0x138, hw_reslo = 0x13A, hw_reshi = 0x13C;

class hw_multiplier {
 public:
  hw_multiplier() {
    uint16_t sr = 0;
    __asm__ volatile("mov r2, %0\n dint\n nop" : "=r"(sr)::"memory");
    gie_ = (sr & 0x0008u) != 0;
  }
  ~hw_multiplier() {
    if (gie_) __asm__ volatile("nop\n eint\n nop" ::: "memory");
  }
  hw_multiplier(const hw_multiplier&) = delete;
  hw_multiplier& operator=(const hw_multiplier&) = delete;
  uint32_t operator()(uint16_t a, uint16_t b) const {
    hw(hw_mpy) = a;
    hw(hw_op2) = b;
    __asm__ volatile("nop" ::: "memory");  // the product is ready after one instruction
    return hw(hw_reslo) | (static_cast<uint32_t>(hw(hw_reshi)) << 16);
  }

 private:
  bool gie_ = false;
};

// The low 64 bits of a x b from the 10 partial products below the 2^64 weight (constant shifts
// only: a variable 64-bit shift would itself call a slow helper).
uint64_t hw_mul64(uint64_t a, uint64_t b) {
  const auto a0 = static_cast<uint16_t>(a), a1 = static_cast<uint16_t>(a >> 16);
  const auto a2 = static_cast<uint16_t>(a >> 32), a3 = static_cast<uint16_t>(a >> 48);
  const auto b0 = static_cast<uint16_t>(b), b1 = static_cast<uint16_t>(b >> 16);
  const auto b2 = static_cast<uint16_t>(b >> 32), b3 = static_cast<uint16_t>(b >> 48);
  const hw_multiplier m;
  const uint64_t w0 = m(a0, b0);
  const uint64_t w1 = uint64_t{m(a0, b1)} + m(a1, b0);
  const uint64_t w2 = uint64_t{m(a0, b2)} + m(a1, b1) + m(a2, b0);
  const auto w3 = static_cast<uint16_t>(m(a0, b3) + m(a1, b2) + m(a2, b1) + m(a3, b0));
  return w0 + (w1 << 16) + (w2 << 32) + (uint64_t{w3} << 48);
}

}  // namespace

// The 16- and 32-bit unsigned divisions in assembly (below): the same restoring division, one
// bit per turn, in ~14 cycles a turn (~470 a 32-bit division; clang's code of the C++ loop took
// ~3 000, and a step's interval needs one). Quotient and remainder in one 64-bit (32-bit) return
// value: R12..R13 the quotient, R14..R15 the remainder (R12 and R13 for 16 bits).
extern "C" uint64_t gyroflip_rt_udivmod32(uint32_t n, uint32_t d);
extern "C" uint32_t gyroflip_rt_udivmod16(uint16_t n, uint16_t d);

namespace {

// Restoring division, one bit per turn. Shifts are by the constant 1 only: a variable shift
// would itself call a helper below. The 16- and 32-bit widths use the assembly versions.
template <class U>
U udivmod(U n, U d, U* rem) {
  if constexpr (sizeof(U) == 4) {
    const uint64_t qr = gyroflip_rt_udivmod32(n, d);
    *rem = static_cast<U>(qr >> 32);
    return static_cast<U>(qr);
  } else if constexpr (sizeof(U) == 2) {
    const uint32_t qr = gyroflip_rt_udivmod16(n, d);
    *rem = static_cast<U>(qr >> 16);
    return static_cast<U>(qr);
  } else if constexpr (sizeof(U) == 8) {
    // The compiler calls __mspabi_divull and __mspabi_remull (assembly, below).
    if (d == 0) {
      *rem = n;
      return static_cast<U>(~U{0});
    }
    *rem = n % d;
    return n / d;
  }
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
  const hw_multiplier m;
  return static_cast<int16_t>(m(static_cast<uint16_t>(a), static_cast<uint16_t>(b)));
}
int32_t __mspabi_mpyl(int32_t a, int32_t b) {
  const auto ua = static_cast<uint32_t>(a), ub = static_cast<uint32_t>(b);
  const auto al = static_cast<uint16_t>(ua), ah = static_cast<uint16_t>(ua >> 16);
  const auto bl = static_cast<uint16_t>(ub), bh = static_cast<uint16_t>(ub >> 16);
  const hw_multiplier m;
  const uint32_t lo = m(al, bl);
  const auto cross = static_cast<uint16_t>(m(al, bh) + m(ah, bl));
  return static_cast<int32_t>(lo + (static_cast<uint32_t>(cross) << 16));
}
int64_t gyroflip_rt_mpyll(int64_t a, int64_t b) {
  return static_cast<int64_t>(hw_mul64(static_cast<uint64_t>(a), static_cast<uint64_t>(b)));
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
GYROFLIP_MSPABI_64(__mspabi_divlli, gyroflip_rt_divlli);
GYROFLIP_MSPABI_64(__mspabi_remlli, gyroflip_rt_remlli);

// n in R12 (R13:R12), d in R13 (R15:R14); the quotient is shifted in where n is shifted out. A
// remainder that carries out of its width is certainly above d. Division by 0 gives all ones
// and the remainder n, as udivmod does (the firmware never divides by 0).
__asm__(
    ".section .text.gyroflip_rt_udivmod32,\"ax\",@progbits\n"
    ".global gyroflip_rt_udivmod32\n"
    ".type gyroflip_rt_udivmod32,@function\n"
    "gyroflip_rt_udivmod32:\n"
    "  push r10\n  push r9\n"
    "  clr r10\n  clr r11\n  mov #32, r9\n"
    "1:\n"
    "  rla r12\n  rlc r13\n  rlc r10\n  rlc r11\n"
    "  jc 2f\n"
    "  cmp r15, r11\n  jlo 3f\n  jne 2f\n"
    "  cmp r14, r10\n  jlo 3f\n"
    "2:\n"
    "  sub r14, r10\n  subc r15, r11\n  bis #1, r12\n"
    "3:\n"
    "  dec r9\n  jnz 1b\n"
    "  mov r10, r14\n  mov r11, r15\n"
    "  pop r9\n  pop r10\n  ret\n"
    ".size gyroflip_rt_udivmod32, .-gyroflip_rt_udivmod32\n");
__asm__(
    ".section .text.gyroflip_rt_udivmod16,\"ax\",@progbits\n"
    ".global gyroflip_rt_udivmod16\n"
    ".type gyroflip_rt_udivmod16,@function\n"
    "gyroflip_rt_udivmod16:\n"
    "  mov r13, r14\n  clr r13\n  mov #16, r15\n"
    "1:\n"
    "  rla r12\n  rlc r13\n"
    "  jc 2f\n"
    "  cmp r14, r13\n  jlo 3f\n"
    "2:\n"
    "  sub r14, r13\n  bis #1, r12\n"
    "3:\n"
    "  dec r15\n  jnz 1b\n"
    "  ret\n"
    ".size gyroflip_rt_udivmod16, .-gyroflip_rt_udivmod16\n");

// The 64-bit unsigned division (special convention: n in R8..R11, d in R12..R15, the result in
// R12..R15, R4..R10 preserved): the same restoring division in ~30 cycles a turn (~2 000 a
// division; the C++ loop took ~20 000, and CONFIGURE's link budget needs three). The remainder
// is R4..R7, the quotient replaces n in R8..R11; the turn count lives on the stack (every
// register holds an operand).
#define GYROFLIP_MSPABI_DIV64(name, result)                                 \
  __asm__(".section .text." #name                                           \
          ",\"ax\",@progbits\n"                                             \
          ".global " #name                                                  \
          "\n"                                                              \
          ".type " #name ",@function\n" #name                               \
          ":\n"                                                             \
          "  push r4\n  push r5\n  push r6\n  push r7\n"                    \
          "  push r8\n  push r9\n  push r10\n"                              \
          "  clr r4\n  clr r5\n  clr r6\n  clr r7\n  push #64\n"            \
          "1:\n"                                                            \
          "  rla r8\n  rlc r9\n  rlc r10\n  rlc r11\n"                      \
          "  rlc r4\n  rlc r5\n  rlc r6\n  rlc r7\n"                        \
          "  jc 2f\n"                                                       \
          "  cmp r15, r7\n  jlo 3f\n  jne 2f\n"                             \
          "  cmp r14, r6\n  jlo 3f\n  jne 2f\n"                             \
          "  cmp r13, r5\n  jlo 3f\n  jne 2f\n"                             \
          "  cmp r12, r4\n  jlo 3f\n"                                       \
          "2:\n"                                                            \
          "  sub r12, r4\n  subc r13, r5\n  subc r14, r6\n  subc r15, r7\n" \
          "  bis #1, r8\n"                                                  \
          "3:\n"                                                            \
          "  sub #1, 0(r1)\n  jnz 1b\n"                                     \
          "  add #2, r1\n" result                                           \
          "  pop r10\n  pop r9\n  pop r8\n"                                 \
          "  pop r7\n  pop r6\n  pop r5\n  pop r4\n  ret\n"                 \
          ".size " #name ", .-" #name "\n")
GYROFLIP_MSPABI_DIV64(__mspabi_divull,
                      "  mov r8, r12\n  mov r9, r13\n  mov r10, r14\n  mov r11, r15\n");
GYROFLIP_MSPABI_DIV64(__mspabi_remull,
                      "  mov r4, r12\n  mov r5, r13\n  mov r6, r14\n  mov r7, r15\n");
