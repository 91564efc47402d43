# Project-wide warning and sanitizer flags, applied through one INTERFACE target so that
# third-party headers (included as SYSTEM) are not affected.
add_library(gyroflip_flags INTERFACE)
target_compile_options(gyroflip_flags INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion -Wnon-virtual-dtor
  -Wold-style-cast -Wcast-align -Woverloaded-virtual -Wnull-dereference -Wdouble-promotion
  -Wformat=2 -Wimplicit-fallthrough)
if(GYROFLIP_WERROR)
  target_compile_options(gyroflip_flags INTERFACE -Werror)
endif()
if(GYROFLIP_SANITIZE)
  target_compile_options(gyroflip_flags INTERFACE -fsanitize=address,undefined -fno-sanitize-recover=all
                                                  -fno-omit-frame-pointer)
  target_link_options(gyroflip_flags INTERFACE -fsanitize=address,undefined)
endif()
