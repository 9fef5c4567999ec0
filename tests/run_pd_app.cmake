# Included by the -P test scripts: runs the '|'-separated command RUN in
# WORKDIR, keeps its output in run.stdout and run.stderr there, echoes it to
# the test log, and leaves the exit code in 'rc'.
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
