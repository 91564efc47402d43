# Include check of the module walls (run by the build, src/CMakeLists.txt): every
# `#include "gyroflip/<m>/..."` in src/<module>/ and include/gyroflip/<module>/ must name the
# module itself or one of the modules it lists as dependencies (docs/ARCHITECTURE.md), and no
# library file may include a CLI header or CLI11. Header-only uses of another module (a struct, an
# inline function) never reach the linker, so the link checks alone would miss them. Also: no
# string literal in the library names a CLI flag (`--rate`): messages name parameters.
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
      elseif(line MATCHES "<CLI/|\"cli|\"cmd_|progress_bar")
        file(RELATIVE_PATH rel "${ROOT}" "${f}")
        list(APPEND failures "${rel}: the library may not include CLI code (${line})")
      endif()
    endforeach()
  endforeach()
endforeach()
if(failures)
  list(JOIN failures "\n" text)
  message(FATAL_ERROR "module walls broken:\n${text}")
endif()
file(WRITE "${STAMP}" "ok\n")
