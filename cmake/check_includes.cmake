# Include check of the module walls (run by the build, src/CMakeLists.txt): every
# `#include "gyroflip/<m>/..."` in src/<module>/ and include/gyroflip/<module>/ must name the
# module itself or one of the modules it lists as dependencies (docs/ARCHITECTURE.md), and no
# library file may include a CLI header or CLI11. Header-only uses of another module (a struct, an
# inline function) never reach the linker, so the link checks alone would miss them. Also: no
# string literal in the library names a CLI flag (`--rate`): messages name parameters.
# The firmware walls (issue 8, docs/FIRMWARE.md): nothing under firmware/ includes a header other
# than <stdint.h>, <stddef.h> or, in its own port, the MCU's <msp430.h>, nor a host library header;
# the host library includes only firmware/protocol/ and the AD7739 fact headers
# (drivers/ad7739/regs.hpp, convert.hpp), which the simulator's ADC model shares with the driver.
# The host side (host/: emulator, serial, recorder) sits above the library: no library file
# includes it.
#   cmake -DROOT=<source dir> -DRULES="core:;earth:core;..." -DSTAMP=<file> -P check_includes.cmake
cmake_minimum_required(VERSION 3.25)
set(failures "")
foreach(rule IN LISTS RULES)
  string(REPLACE ":" ";" parts "${rule}")
  list(GET parts 0 module)
  list(LENGTH parts n)
  set(allowed ${module})
  if(n GREATER 1 AND NOT "${parts}" MATCHES ";$")
    list(GET parts 1 deps)
    string(REPLACE "," ";" deps "${deps}")
    list(APPEND allowed ${deps})
  endif()
  file(GLOB_RECURSE files "${ROOT}/src/${module}/*.cpp" "${ROOT}/src/${module}/*.hpp"
       "${ROOT}/include/gyroflip/${module}/*.hpp")
  foreach(f IN LISTS files)
    file(STRINGS "${f}" lines REGEX "^[ \t]*#[ \t]*include")
    # The library never names a CLI flag (its messages name parameters; apps/ maps them).
    file(STRINGS "${f}" flagged REGEX "\"[^\"]*[ (']--[a-z][a-z-]+")
    foreach(line IN LISTS flagged)
      if(NOT line MATCHES "^[ \t]*//")
        file(RELATIVE_PATH rel "${ROOT}" "${f}")
        list(APPEND failures "${rel}: the library names a CLI flag in: ${line}")
      endif()
    endforeach()
    foreach(line IN LISTS lines)
      if(line MATCHES "\"gyroflip/([a-z_]+)/")
        if(NOT CMAKE_MATCH_1 IN_LIST allowed)
          file(RELATIVE_PATH rel "${ROOT}" "${f}")
          list(APPEND failures "${rel}: module '${module}' includes '${CMAKE_MATCH_1}', which it may not use (allowed: ${allowed}; docs/ARCHITECTURE.md)")
        endif()
      elseif(line MATCHES "\"(firmware/[^\"]+)\"" AND
             NOT CMAKE_MATCH_1 MATCHES "^firmware/(protocol/|drivers/ad7739/(regs|convert)\\.hpp$)")
        file(RELATIVE_PATH rel "${ROOT}" "${f}")
        list(APPEND failures "${rel}: the library may include only firmware/protocol/ and the AD7739 fact headers of firmware/ (${line})")
      elseif(line MATCHES "\"host/")
        file(RELATIVE_PATH rel "${ROOT}" "${f}")
        list(APPEND failures "${rel}: the library may not include the host side above it (${line})")
      elseif(line MATCHES "<CLI/|\"cli|\"cmd_|progress_bar")
        file(RELATIVE_PATH rel "${ROOT}" "${f}")
        list(APPEND failures "${rel}: the library may not include CLI code (${line})")
      endif()
    endforeach()
  endforeach()
endforeach()
file(GLOB_RECURSE fw_files "${ROOT}/firmware/*.cpp" "${ROOT}/firmware/*.hpp" "${ROOT}/firmware/*.c"
     "${ROOT}/firmware/*.h")
foreach(f IN LISTS fw_files)
  file(RELATIVE_PATH rel "${ROOT}" "${f}")
  file(STRINGS "${f}" lines REGEX "^[ \t]*#[ \t]*include")
  foreach(line IN LISTS lines)
    if(line MATCHES "<([^>]+)>")
      set(header "${CMAKE_MATCH_1}")
      if(NOT header MATCHES "^std(int|def)\\.h$" AND
         NOT (rel MATCHES "^firmware/ports/msp430f149/" AND header STREQUAL "msp430.h"))
        list(APPEND failures "${rel}: the firmware is freestanding, <stdint.h> and <stddef.h> only (${line})")
      endif()
    elseif(line MATCHES "\"gyroflip/")
      list(APPEND failures "${rel}: the firmware may not include a host library header (${line})")
    endif()
  endforeach()
endforeach()
if(failures)
  list(JOIN failures "\n" text)
  message(FATAL_ERROR "module walls broken:\n${text}")
endif()
file(WRITE "${STAMP}" "ok\n")
