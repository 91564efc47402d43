/// \file
/// \brief Fields one side of an interrupt writes and the other reads (the firmware core's step
/// queue and conversion results, shared with a port's interrupt handlers). Each field is written
/// by one side only and is at most 16 bits wide, so one MSP430 instruction moves it: no lock.
/// The accesses go through volatile glvalues, so the compiler neither caches nor merges them,
/// while the objects stay constant-initialisable (a volatile member would make the device
/// object non-literal, and it is `constinit` on the MSP430F149); barrier() keeps the plain
/// accesses to a slot on their side of the index that publishes it.
#pragma once

namespace gyroflip::fw {

template <class T>
[[nodiscard]] inline T shared(const T& x) {
  return *static_cast<const volatile T*>(&x);
}

template <class T>
inline void share(T& x, T v) {
  *static_cast<volatile T*>(&x) = v;
}

/// A compiler barrier: no memory access moves across it (single core: no fence needed).
inline void barrier() {
  __asm__ volatile("" ::: "memory");
}

}  // namespace gyroflip::fw
