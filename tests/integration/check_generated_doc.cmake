# SPDX-License-Identifier: MIT
# A document, or one block of it, must be exactly what pneufracd prints, so
# that what docs/ shows cannot drift from the tables in code.
#   cmake -DDAEMON=<pneufracd> -DARG=<--print-register-map|--help> -DDOC=<file>
#         -DOUT=<file for the expected text>
#         [-DBEGIN=<line before the block> -DEND=<line after it>]
#         -P check_generated_doc.cmake
# With BEGIN and END the block is the output fenced as ```text.
execute_process(COMMAND "${DAEMON}" "${ARG}" OUTPUT_VARIABLE want RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pneufracd ${ARG} failed (${rc})")
endif()
file(READ "${DOC}" have)
if(DEFINED BEGIN)
  set(want "```text\n${want}```\n")
  string(FIND "${have}" "${BEGIN}\n" b)
  string(FIND "${have}" "\n${END}\n" e)
  if(b EQUAL -1 OR e EQUAL -1 OR e LESS b)
    message(FATAL_ERROR "${DOC}: no block between '${BEGIN}' and '${END}'")
  endif()
  string(LENGTH "${BEGIN}\n" skip)
  math(EXPR b "${b} + ${skip}")
  math(EXPR n "${e} + 1 - ${b}")
  string(SUBSTRING "${have}" ${b} ${n} have)
  set(how "replace the block between '${BEGIN}' and '${END}' in ${DOC} with ${OUT}")
else()
  set(how "cp ${OUT} ${DOC}")
endif()
file(WRITE "${OUT}" "${want}")
if(NOT have STREQUAL want)
  message(FATAL_ERROR "${DOC} is out of date with `pneufracd ${ARG}`; ${how}")
endif()
