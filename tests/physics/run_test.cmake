# Runs one physics test (cmake -P). Variables (lists separated by '|'):
#   RUN        the command, e.g. mpirun|-np|2|pd_app|case.prm
#   WORKDIR    a fresh directory the command runs in
#   EXPECT     'success' (exit code 0) or 'error' (non-zero exit code)
#   REGEX      optional: must match stdout + stderr of RUN
#   CHECK      optional: a second command, run in WORKDIR after RUN; must exit 0
#   EXPECTED   optional: a stored output; the stdout of CHECK (or of RUN
#              without CHECK) must match it under numdiff
#   NUMDIFF, NUMDIFF_ARGS  the numdiff executable and its tolerances
foreach(var RUN WORKDIR EXPECT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_test.cmake: ${var} is not set")
  endif()
endforeach()

file(REMOVE_RECURSE "${WORKDIR}")
file(MAKE_DIRECTORY "${WORKDIR}")

include("${CMAKE_CURRENT_LIST_DIR}/../run_pd_app.cmake")
run_pd_app()
message("---- exit code ${rc}")

if(EXPECT STREQUAL "success" AND NOT rc EQUAL 0)
  message(FATAL_ERROR "expected success, got exit code ${rc}")
elseif(EXPECT STREQUAL "error" AND (rc EQUAL 0 OR NOT rc MATCHES "^[0-9]+$"))
  message(FATAL_ERROR "expected an error exit code, got '${rc}'")
endif()
if(DEFINED REGEX AND NOT "${out}${err}" MATCHES "${REGEX}")
  message(FATAL_ERROR "the output does not match '${REGEX}'")
endif()

set(compared "${out}")
if(DEFINED CHECK)
  run_check()
  set(compared "${check_out}")
endif()

if(DEFINED EXPECTED)
  file(WRITE "${WORKDIR}/compared.txt" "${compared}")
  string(REPLACE "|" ";" numdiff_args "${NUMDIFF_ARGS}")
  execute_process(COMMAND "${NUMDIFF}" ${numdiff_args} "${EXPECTED}" "${WORKDIR}/compared.txt"
    OUTPUT_VARIABLE diff_out RESULT_VARIABLE diff_rc)
  if(NOT diff_rc EQUAL 0)
    message(FATAL_ERROR "numdiff ${NUMDIFF_ARGS}: ${WORKDIR}/compared.txt differs from ${EXPECTED}\n${diff_out}")
  endif()
  message("---- numdiff ${NUMDIFF_ARGS} against ${EXPECTED}: equal")
endif()
