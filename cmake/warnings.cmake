# Project-wide warning, floating-point and sanitizer flags, applied through one INTERFACE target so that
# third-party headers (included as SYSTEM) are not affected.
add_library(gyroflip_flags INTERFACE)
target_compile_options(gyroflip_flags INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion -Wnon-virtual-dtor
  -Wold-style-cast -Wcast-align -Woverloaded-virtual -Wnull-dereference -Wdouble-promotion
  -Wformat=2 -Wimplicit-fallthrough)
# No fused multiply-add contraction: a seed must give the same recording on every machine, and
# GCC contracts a*b+c by default in C++ wherever the target has FMA (arm64, x86-64-v3), which
# changes roundings (the simulator's round-to-even trick among them).
target_compile_options(gyroflip_flags INTERFACE -ffp-contract=off)
if(GYROFLIP_WERROR)
  target_compile_options(gyroflip_flags INTERFACE -Werror)
endif()
if(GYROFLIP_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "GYROFLIP_FUZZ needs clang (libFuzzer): CXX=clang++ (scripts/fuzz)")
  endif()
  # Every object instrumented for coverage and the sanitizers; the targets link libFuzzer.
  target_compile_options(gyroflip_flags INTERFACE -fsanitize=fuzzer-no-link,address,undefined,float-cast-overflow
                                                  -fno-sanitize-recover=all -fno-omit-frame-pointer -g)
  target_link_options(gyroflip_flags INTERFACE -fsanitize=address,undefined,float-cast-overflow)
endif()
if(GYROFLIP_SANITIZE)
  target_compile_options(gyroflip_flags INTERFACE -fsanitize=address,undefined,float-cast-overflow
                                                  -fno-sanitize-recover=all
                                                  -fno-omit-frame-pointer)
  # GCC 12 with the sanitizers at -O1 reports maybe-uninitialized inside libstdc++'s <regex>
  # (std::function in _NFA::_M_insert_subexpr_*, which initialises it: a false positive; the
  # warning depends on the optimiser's view, which the instrumentation changes). The Release
  # build keeps it as an error.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(gyroflip_flags INTERFACE -Wno-maybe-uninitialized)
  endif()
  target_link_options(gyroflip_flags INTERFACE -fsanitize=address,undefined,float-cast-overflow)
endif()
