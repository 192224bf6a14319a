# SPDX-License-Identifier: MIT
# Run a command and write its standard output to a file, failing on a
# non-zero exit (add_custom_command has no portable redirection).
#   cmake -DOUT=<file> -DCMD=<program;arg;...> -P run_to_file.cmake
execute_process(COMMAND ${CMD} OUTPUT_FILE "${OUT}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  file(REMOVE "${OUT}")
  message(FATAL_ERROR "command failed (${rc}): ${CMD}")
endif()
