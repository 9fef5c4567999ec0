# Read by ctest when it starts (TEST_INCLUDE_FILES, see CMakeLists.txt): adds
# models.NAME.np1 and models.NAME.np2 for every material the program lists.
# If the list cannot be made (the program is not built, or it lists nothing),
# the failing test models.registry says so: the suite never vanishes silently.
execute_process(COMMAND "${PROGRAM}" --list
  OUTPUT_VARIABLE names ERROR_VARIABLE list_error RESULT_VARIABLE list_rc)
string(STRIP "${names}" names)
if(NOT list_rc EQUAL 0 OR names STREQUAL "")
  add_test(models.registry "${CMAKE_EXECUTABLE}" -E echo
    "Error: '${PROGRAM} --list' gave no materials (exit code ${list_rc}): ${list_error}")
  set_tests_properties(models.registry PROPERTIES WILL_FAIL TRUE LABELS models)
  return()
endif()
string(REPLACE "\n" ";" names "${names}")
foreach(name IN LISTS names)
  foreach(np 1 2)
    set(test "models.${name}.np${np}")
    # The one runner's check mode (tests/tools/run.sh): both rank counts
    # against the one stored NAME.output; without one, every check still
    # runs and the test then fails saying where the output goes.
    set(expected "${SOURCE_DIR}/${name}.output")
    if(EXISTS "${expected}")
      add_test("${test}" "${RUNNER}" check --workdir "${BINARY_DIR}/${test}" --expected "${expected}"
        --numdiff-arg -q --numdiff-arg -a --numdiff-arg 1e-9 --numdiff-arg -r --numdiff-arg 1e-6
        -- "${MPIRUN}" -np ${np} "${PROGRAM}" "${name}")
    else()
      add_test("${test}" "${RUNNER}" check --workdir "${BINARY_DIR}/${test}"
        -- "${MPIRUN}" -np ${np} "${PROGRAM}" "${name}"
        --- sh -c "echo 'no stored output ${expected} for this material (every check above passed): review ${BINARY_DIR}/${test}/run.stdout and copy it there; 1 and 2 ranks are compared against it'; exit 1")
    endif()
    set_tests_properties("${test}" PROPERTIES ENVIRONMENT "${ENVIRONMENT}"
      PROCESSORS ${np} TIMEOUT 300 LABELS models)
  endforeach()
endforeach()
