# Runs one material's conformance checks (cmake -P; the variables of
# tests/physics/run_test.cmake). A new material has no stored output yet:
# its checks still run, then the test fails saying where the output goes.
if(NOT EXISTS "${EXPECTED}")
  set(missing "${EXPECTED}")
  unset(EXPECTED CACHE)
endif()
include("${CMAKE_CURRENT_LIST_DIR}/../physics/run_test.cmake")
if(missing)
  file(WRITE "${WORKDIR}/compared.txt" "${out}")
  message(FATAL_ERROR "no stored output ${missing} for this material (every check above passed): "
    "review ${WORKDIR}/compared.txt and copy it there; 1 and 2 ranks are compared against it")
endif()
