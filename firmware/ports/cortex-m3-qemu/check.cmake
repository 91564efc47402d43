# The Cortex-M3 image: prints its size and fails when it links floating-point helpers, the
# heap or the C++ runtime (the firmware has none of them).   cmake -DELF=... -P check.cmake
execute_process(COMMAND arm-none-eabi-nm ${ELF} OUTPUT_VARIABLE syms COMMAND_ERROR_IS_FATAL ANY)
string(REGEX MATCHALL "[^\n]*(__aeabi_[fd][a-z0-9]*|__(add|sub|mul|div)[sd]f3|malloc|_sbrk|__cxa_[a-z_]+)[^\n]*"
       bad "${syms}")
if(bad)
  message(FATAL_ERROR "cortex-m3: the image links forbidden symbols:\n${bad}")
endif()
execute_process(COMMAND arm-none-eabi-size ${ELF} OUTPUT_VARIABLE size COMMAND_ERROR_IS_FATAL ANY)
message(STATUS "cortex-m3 image:\n${size}")
