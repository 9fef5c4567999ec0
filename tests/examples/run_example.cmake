# Runs one example test (cmake -P). Variables (lists separated by '|'):
#   RUN          the command, run in WORKDIR, e.g. mpirun|-np|2|pd_app|case.prm
#   WORKDIR      a fresh directory the command runs in (removed first)
#   PRM          parameter files: the first, with the 'set' lines of the
#                others applied in order (merge_prm.py), is WORKDIR/case.prm;
#                @PERIDEAL_SOURCE_DIR@ in them becomes SOURCE_DIR
#   SOURCE_DIR   the source tree
#   CSV          the globals CSV the run writes, relative to WORKDIR
#   REGEX        optional: must match the standard output of RUN
#   LAST_ROW_MIN optional: column|minimum pairs; the last row of CSV must
#                have column >= minimum (e.g. broken_bonds|1)
#   CHECK        optional: a command run in WORKDIR after RUN; must exit 0
#   EXPECTED     optional: a stored file; WORKDIR/compared.txt (the set-up report's
#                points, bonds and block lines, then CSV, or the standard
#                output of CHECK if there is one) must match it
#   NUMDIFF, NUMDIFF_ARGS  the numdiff executable and its tolerances
foreach(var RUN WORKDIR PRM SOURCE_DIR CSV)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_example.cmake: ${var} is not set")
  endif()
endforeach()

file(REMOVE_RECURSE "${WORKDIR}")
file(MAKE_DIRECTORY "${WORKDIR}")

# pd_app refuses a key or subsection given twice: the later files are
# overlays merged into the first (merge_prm.py), not appended.
string(REPLACE "|" ";" prm_files "${PRM}")
list(LENGTH prm_files n_prm)
if(n_prm GREATER 1)
  if(NOT DEFINED PYTHON)
    message(FATAL_ERROR "run_example.cmake: PYTHON is not set (needed to merge ${PRM})")
  endif()
  execute_process(COMMAND ${PYTHON} ${CMAKE_CURRENT_LIST_DIR}/merge_prm.py ${prm_files}
    OUTPUT_VARIABLE prm RESULT_VARIABLE merge_rc)
  if(NOT merge_rc EQUAL 0)
    message(FATAL_ERROR "merge_prm.py ${prm_files} failed: ${merge_rc}")
  endif()
else()
  file(READ "${prm_files}" prm)
endif()
string(REPLACE "@PERIDEAL_SOURCE_DIR@" "${SOURCE_DIR}" prm "${prm}")
file(WRITE "${WORKDIR}/case.prm" "${prm}")

include("${CMAKE_CURRENT_LIST_DIR}/../run_pd_app.cmake")
run_pd_app()
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pd_app failed: exit code '${rc}'")
endif()
if(DEFINED REGEX AND NOT "${out}" MATCHES "${REGEX}")
  message(FATAL_ERROR "the output does not match '${REGEX}'")
endif()

if(NOT EXISTS "${WORKDIR}/${CSV}")
  message(FATAL_ERROR "the run wrote no ${WORKDIR}/${CSV}")
endif()
file(STRINGS "${WORKDIR}/${CSV}" rows)
list(GET rows 0 header)
list(GET rows -1 last)
string(REPLACE "," ";" header "${header}")
string(REPLACE "," ";" last "${last}")

if(DEFINED LAST_ROW_MIN)
  string(REPLACE "|" ";" pairs "${LAST_ROW_MIN}")
  list(LENGTH pairs n)
  math(EXPR n "${n} - 1")
  foreach(i RANGE 0 ${n} 2)
    math(EXPR j "${i} + 1")
    list(GET pairs ${i} column)
    list(GET pairs ${j} minimum)
    list(FIND header "${column}" c)
    if(c LESS 0)
      message(FATAL_ERROR "${CSV} has no column '${column}'")
    endif()
    list(GET last ${c} value)
    if(value LESS minimum)
      message(FATAL_ERROR "${column} = ${value} in the last row of ${CSV}, expected >= ${minimum}")
    endif()
    message("---- last row: ${column} = ${value} >= ${minimum}")
  endforeach()
endif()

if(DEFINED CHECK)
  run_check()
endif()

if(DEFINED EXPECTED)
  # The set-up report's lines that do not depend on the rank count (before
  # the first line of the time integration: 'Time integration',
  # 'Quasistatic:' or 'Newmark:'), then the CSV.
  # (';' would split the lines as a CMake list: keep it out of the way.)
  set(setup_end -1)
  foreach(start "\nTime integration" "\nQuasistatic:" "\nNewmark:")
    string(FIND "${out}" "${start}" at)
    if(at GREATER -1 AND (setup_end EQUAL -1 OR at LESS setup_end))
      set(setup_end ${at})
    endif()
  endforeach()
  string(SUBSTRING "${out}" 0 ${setup_end} safe)
  string(REPLACE ";" "<semicolon>" safe "${safe}")
  string(REGEX MATCHALL "(^|\n)  (points|bonds|block '[^\n]*'):[^\n]*" setup "${safe}")
  set(output "")
  foreach(line ${setup})
    string(REGEX REPLACE "^\n" "" line "${line}")
    string(REGEX REPLACE " \\(nonlocal ghosts: [0-9]+\\)" "" line "${line}")
    string(APPEND output "${line}\n")
  endforeach()
  string(REPLACE "<semicolon>" ";" output "${output}")
  if(DEFINED CHECK)
    string(APPEND output "${check_out}")
  else()
    file(READ "${WORKDIR}/${CSV}" csv)
    string(APPEND output "${csv}")
  endif()
  file(WRITE "${WORKDIR}/compared.txt" "${output}")
  string(REPLACE "|" ";" numdiff_args "${NUMDIFF_ARGS}")
  execute_process(COMMAND "${NUMDIFF}" ${numdiff_args} "${EXPECTED}" "${WORKDIR}/compared.txt"
    OUTPUT_VARIABLE diff_out RESULT_VARIABLE diff_rc)
  if(NOT diff_rc EQUAL 0)
    message(FATAL_ERROR "numdiff ${NUMDIFF_ARGS}: ${WORKDIR}/output differs from ${EXPECTED}\n${diff_out}")
  endif()
  message("---- numdiff ${NUMDIFF_ARGS} against ${EXPECTED}: equal")
endif()
