# MSP430 with clang and ld.lld (Debian 12 has no msp430-gcc; STACK.md §6): the clang driver
# cannot link for msp430, so CMake calls ld.lld directly.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR msp430)
set(CMAKE_C_COMPILER clang)
set(CMAKE_CXX_COMPILER clang++)
set(CMAKE_C_COMPILER_TARGET msp430)
set(CMAKE_CXX_COMPILER_TARGET msp430)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
find_program(GYROFLIP_LLD ld.lld REQUIRED)
set(CMAKE_CXX_LINK_EXECUTABLE
    "${GYROFLIP_LLD} -m msp430elf <LINK_FLAGS> <OBJECTS> -o <TARGET> <LINK_LIBRARIES>")
