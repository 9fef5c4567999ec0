# Included by the -P test scripts. run_pd_app() runs the '|'-separated command
# RUN in WORKDIR, keeps its output in run.stdout and run.stderr there, echoes
# it to the test log, and leaves the exit code in 'rc'. run_check() runs the
# '|'-separated command CHECK in WORKDIR, echoes its output, leaves its
# standard output in 'check_out' and fails the test unless it exits with 0.
macro(run_pd_app)
  string(REPLACE "|" ";" run "${RUN}")
  execute_process(COMMAND ${run}
    WORKING_DIRECTORY "${WORKDIR}"
    OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
  file(WRITE "${WORKDIR}/run.stdout" "${out}")
  file(WRITE "${WORKDIR}/run.stderr" "${err}")
  message("---- ${RUN}\n${out}")
  if(err)
    message("---- stderr\n${err}")
  endif()
endmacro()

macro(run_check)
  string(REPLACE "|" ";" check "${CHECK}")
  execute_process(COMMAND ${check}
    WORKING_DIRECTORY "${WORKDIR}"
    OUTPUT_VARIABLE check_out ERROR_VARIABLE check_err RESULT_VARIABLE check_rc)
  message("---- ${CHECK}\n${check_out}${check_err}")
  if(NOT check_rc EQUAL 0)
    message(FATAL_ERROR "the check failed (exit code ${check_rc})")
  endif()
endmacro()
