# gyroflip_build_commit(TARGET OUT): a target that writes OUT (cmake/build_commit.cmake's C++
# fragment: the commit, `+modified` for a tree that differs from it) at every build, before
# anything that depends on TARGET. The script rewrites OUT only when its text changes, and OUT is
# a byproduct (Ninja restats it), so a build with nothing new rebuilds nothing; an edit of the
# tree after CMake configured is seen at the next build (review of issue 31: the commit was looked
# up when CMake configured alone, so a binary built from an edited tree said it was the commit's).
function(gyroflip_build_commit target out)
  add_custom_target(${target}
                    COMMAND ${CMAKE_COMMAND} -DSRC=${PROJECT_SOURCE_DIR} -DOUT=${out} -P
                            ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/build_commit.cmake
                    BYPRODUCTS ${out}
                    COMMENT "Looking up the commit the build is made from"
                    VERBATIM)
endfunction()
