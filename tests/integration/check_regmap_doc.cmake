# SPDX-License-Identifier: MIT
# docs/register-map.md must be exactly what `pneufracd --print-register-map`
# prints, so the documented map cannot drift from the table in code.
#   cmake -DDAEMON=<pneufracd> -DDOC=<docs/register-map.md> -DOUT=<tmp> -P check_regmap_doc.cmake
execute_process(COMMAND "${DAEMON}" --print-register-map OUTPUT_FILE "${OUT}"
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pneufracd --print-register-map failed (${rc})")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" -E compare_files "${OUT}" "${DOC}"
                RESULT_VARIABLE diff)
if(NOT diff EQUAL 0)
  message(FATAL_ERROR "${DOC} is out of date; regenerate it with\n"
          "  ${DAEMON} --print-register-map > ${DOC}")
endif()
