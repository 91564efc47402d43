# Writes OUT (a C++ fragment) with the git commit the build is made from: `abc123...` (40 hex),
# `+modified` when the tracked files differ from it (staged or not; untracked files are not
# looked at), `unknown` outside a git checkout. Run at every build (build_commit_target.cmake);
# the file is rewritten only when that changes, so a build without a change rebuilds nothing.
#   cmake -DSRC=<source dir> -DOUT=<file> -P build_commit.cmake
set(commit unknown)
find_program(GIT git)
if(GIT)
  execute_process(COMMAND ${GIT} -C ${SRC} rev-parse HEAD OUTPUT_VARIABLE head
                  OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE rc)
  if(rc EQUAL 0 AND head MATCHES "^[0-9a-f]+$")
    set(commit ${head})
    execute_process(COMMAND ${GIT} -C ${SRC} diff --quiet HEAD -- ERROR_QUIET RESULT_VARIABLE dirty)
    if(NOT dirty EQUAL 0)
      string(APPEND commit "+modified")
    endif()
  endif()
endif()
set(text "// Made by cmake/build_commit.cmake at build time.\n#define GYROFLIP_BUILD_COMMIT \"${commit}\"\n")
if(EXISTS ${OUT})
  file(READ ${OUT} old)
endif()
if(NOT "${old}" STREQUAL "${text}")
  file(WRITE ${OUT} "${text}")
endif()
