# Renders `gyroflip --help` and `gyroflip SUB --help` of every subcommand as man pages (troff, the
# help text kept verbatim in a no-fill block): run by cmake/install.cmake with EXE, VERSION, OUT.
# The subcommands and their one-line descriptions are read from `gyroflip --help` itself, so a new
# subcommand gets its page without a list to keep: each page's NAME line is its own description,
# and SEE ALSO names gyroflip(1) and every other page.
file(MAKE_DIRECTORY ${OUT})
file(GLOB stale ${OUT}/*.1)
if(stale)
  file(REMOVE ${stale})  # a subcommand that went takes its page with it
endif()

function(help_of args out_var)
  execute_process(COMMAND ${EXE} ${args} --help OUTPUT_VARIABLE help RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${EXE} ${args} --help failed (${rc})")
  endif()
  set(${out_var} "${help}" PARENT_SCOPE)
endfunction()

# troff: a backslash is written \e; a line starting with . or ' would be a request.
function(troff_text text out_var)
  string(REPLACE "\\" "\\e" text "${text}")
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" text "${text}")
  set(${out_var} "${text}" PARENT_SCOPE)
endfunction()

# The subcommands: the lines "  NAME   description" after "Subcommands:" in the main help.
help_of("" main_help)
string(FIND "${main_help}" "\nSubcommands:\n" at)
if(at LESS 0)
  message(FATAL_ERROR "${EXE} --help lists no subcommands")
endif()
string(SUBSTRING "${main_help}" ${at} -1 listing)
string(REPLACE "\n" ";" lines "${listing}")
set(subcommands)
foreach(line IN LISTS lines)
  if(line MATCHES "^  ([a-z][a-z0-9-]*)  +(.+)$")
    list(APPEND subcommands ${CMAKE_MATCH_1})
    set(summary_${CMAKE_MATCH_1} "${CMAKE_MATCH_2}")
  endif()
endforeach()
list(LENGTH subcommands count)
if(count EQUAL 0)
  message(FATAL_ERROR "no subcommand found in ${EXE} --help")
endif()
# The main page's summary: the first line of the main help, without the program's name.
string(REGEX MATCH "^[^\n]*" first "${main_help}")
string(REGEX REPLACE "^gyroflip: *" "" summary_gyroflip "${first}")

set(pages gyroflip)
foreach(sub IN LISTS subcommands)
  list(APPEND pages gyroflip-${sub})
endforeach()

function(render name args summary)
  help_of("${args}" help)
  troff_text("${help}" help)
  troff_text("${summary}" summary)
  string(TOUPPER ${name} title)
  set(see_also)
  foreach(other IN LISTS pages)
    if(NOT other STREQUAL name)
      list(APPEND see_also "\\fB${other}\\fR(1)")
    endif()
  endforeach()
  list(JOIN see_also ",\n" see_also)
  file(WRITE ${OUT}/${name}.1
       ".TH ${title} 1 \"\" \"gyroflip ${VERSION}\" \"gyroflip manual\"\n"
       ".SH NAME\n${name} \\- ${summary}\n"
       ".SH DESCRIPTION\n.nf\n${help}.fi\n"
       ".SH SEE ALSO\n${see_also};\nthe project's README.md and docs/ (docs/cli.md: every option).\n")
endfunction()

render(gyroflip "" "${summary_gyroflip}")
foreach(sub IN LISTS subcommands)
  render(gyroflip-${sub} ${sub} "${summary_${sub}}")
endforeach()
file(WRITE ${OUT}/pages.stamp "${pages}\n")
