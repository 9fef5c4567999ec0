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
    add_test("${test}" "${CMAKE_EXECUTABLE}"
      "-DRUN=${MPIRUN}|-np|${np}|${PROGRAM}|${name}"
      "-DWORKDIR=${BINARY_DIR}/${test}"
      -DEXPECT=success
      "-DEXPECTED=${SOURCE_DIR}/${name}.output"
      "-DNUMDIFF=${NUMDIFF}"
      "-DNUMDIFF_ARGS=-q|-a|1e-9|-r|1e-6"
      -P "${SOURCE_DIR}/run_model.cmake")
    set_tests_properties("${test}" PROPERTIES ENVIRONMENT "${ENVIRONMENT}"
      PROCESSORS ${np} TIMEOUT 300 LABELS models)
  endforeach()
endforeach()
