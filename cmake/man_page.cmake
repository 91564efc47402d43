# Renders `gyroflip --help` and `gyroflip SUB --help` as man pages (troff, the help text kept
# verbatim in a no-fill block): run by cmake/install.cmake with EXE, SUBCOMMANDS, VERSION, OUT.
file(MAKE_DIRECTORY ${OUT})
function(render name args)
  execute_process(COMMAND ${EXE} ${args} --help OUTPUT_VARIABLE help RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${EXE} ${args} --help failed (${rc})")
  endif()
  # troff: a backslash is written \e; a line starting with . or ' would be a request.
  string(REPLACE "\\" "\\e" help "${help}")
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" help "${help}")
  string(TOUPPER ${name} title)
  file(WRITE ${OUT}/${name}.1
       ".TH ${title} 1 \"\" \"gyroflip ${VERSION}\" \"gyroflip manual\"\n"
       ".SH NAME\n${name} \\- bias-drift compensation of MEMS gyroscopes by sign reversal\n"
       ".SH DESCRIPTION\n.nf\n${help}.fi\n"
       ".SH SEE ALSO\ngyroflip(1), the project's README.md and docs/\n")
endfunction()
render(gyroflip "")
foreach(sub IN LISTS SUBCOMMANDS)
  render(gyroflip-${sub} ${sub})
endforeach()
