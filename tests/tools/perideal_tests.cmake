# The functions every folder of the suite defines its tests with. Each test
# runs through the one runner, tests/tools/run.sh (its modes: error, output,
# interrupt, restart, check; error with -k: a refused run changes no file), and checks a run's CSV and output with the one checker
# program, perideal_check (tests/tools/check.h and check_*.cc); the C++ test
# programs share check.h through tests/physics/harness.h.
#
# A folder sets perideal_test_group (input, physics, ...): its tests are named
# GROUP.NAME.npN and labelled GROUP.

set(PERIDEAL_RUN ${CMAKE_CURRENT_LIST_DIR}/run.sh)
set(PERIDEAL_PD_APP $<TARGET_FILE:pd_app>)
set(PERIDEAL_CHECK $<TARGET_FILE:perideal_check>)

add_executable(perideal_check
  ${CMAKE_CURRENT_LIST_DIR}/perideal_check.cc
  ${CMAKE_CURRENT_LIST_DIR}/check_globals.cc
  ${CMAKE_CURRENT_LIST_DIR}/check_quasistatic.cc
  ${CMAKE_CURRENT_LIST_DIR}/check_stability.cc
  ${CMAKE_CURRENT_LIST_DIR}/check_damage.cc
  ${CMAKE_CURRENT_LIST_DIR}/check_contact.cc
  ${CMAKE_CURRENT_LIST_DIR}/check_fields.cc)
# The fields mode inflates the .vtu arrays deal.II compresses with zlib.
find_package(ZLIB REQUIRED)
target_link_libraries(perideal_check ZLIB::ZLIB)

# perideal_add_test(TEST NP TIMEOUT COMMAND...): one ctest case on NP ranks
# with the suite's environment, labelled ${perideal_test_group}.
# numdiff splits fields at whitespace only by default: a CSV row would be one
# field, compared as text. NUMDIFF_ARGS with these split at commas too, so
# the tolerances apply.
set(CSV_SEPARATORS -s " \\t\\n,")

function(perideal_add_test test np timeout)
  add_test(NAME ${test} COMMAND ${ARGN} WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
  set_tests_properties(${test} PROPERTIES ENVIRONMENT "${PERIDEAL_TEST_ENVIRONMENT}"
    PROCESSORS ${np} TIMEOUT ${timeout} LABELS ${perideal_test_group})
endfunction()

# perideal_pd_app_command(VAR NP): pd_app itself on 1 rank, under mpirun on more.
function(perideal_pd_app_command var np)
  if(np EQUAL 1)
    set(${var} ${PERIDEAL_PD_APP} PARENT_SCOPE)
  else()
    set(${var} ${PERIDEAL_MPIRUN} -np ${np} ${PERIDEAL_PD_APP} PARENT_SCOPE)
  endif()
endfunction()

# perideal_error_test(NAME NP REGEX re [STDOUT re...] [MEMORY_LIMIT kib]
#                     [FILE_LIMIT kib] [UNCHANGED prepare] [FIFO path]
#                     [TIMEOUT s] COMMAND ...): COMMAND must fail
# cleanly with a line 'Error: ' on standard error, which matches REGEX
# (extended, line by line); standard output matches each STDOUT; with
# MEMORY_LIMIT its virtual memory is limited to that many KiB; with
# FILE_LIMIT a file it writes to that many KiB (a write beyond fails as on a
# full disk); FIFO is made first (a named pipe nothing writes to). UNCHANGED:
# COMMAND runs in a new directory where the shell text PREPARE has made files
# first, and every file there must be byte for byte as before, none added or
# removed (a refused run changes nothing). Runner mode 'error'.
function(perideal_error_test name np)
  cmake_parse_arguments(T "" "REGEX;MEMORY_LIMIT;FILE_LIMIT;UNCHANGED;FIFO;TIMEOUT" "STDOUT;COMMAND" ${ARGN})
  set(runner ${PERIDEAL_RUN})
  if(T_FIFO)
    list(APPEND runner --fifo ${T_FIFO})
  endif()
  list(APPEND runner error)
  if(T_MEMORY_LIMIT)
    list(APPEND runner -v ${T_MEMORY_LIMIT})
  endif()
  if(T_FILE_LIMIT)
    list(APPEND runner -f ${T_FILE_LIMIT})
  endif()
  if(DEFINED T_UNCHANGED)
    list(APPEND runner -k ${T_UNCHANGED})
  endif()
  foreach(re ${T_STDOUT})
    list(APPEND runner -o ${re})
  endforeach()
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 120)
  endif()
  perideal_add_test(${perideal_test_group}.${name}.np${np} ${np} ${T_TIMEOUT}
    ${runner} ${T_REGEX} ${T_COMMAND})
endfunction()

# perideal_pd_app_error_test(NAME REGEX [NP...]): pd_app on the calling
# folder's NAME.prm must fail with a message matching REGEX, on each rank count
# given (default 1). A NAME.prm.in is configured first (@CMAKE_CURRENT_SOURCE_DIR@:
# files beside it, e.g. meshes).
function(perideal_pd_app_error_test name regex)
  set(ranks ${ARGN})
  if(NOT ranks)
    set(ranks 1)
  endif()
  set(prm ${CMAKE_CURRENT_SOURCE_DIR}/${name}.prm)
  if(EXISTS ${prm}.in)
    set(prm ${CMAKE_CURRENT_BINARY_DIR}/${name}.prm)
    configure_file(${name}.prm.in ${prm} @ONLY)
  endif()
  foreach(np ${ranks})
    perideal_pd_app_command(run ${np})
    perideal_error_test(${name} ${np} REGEX "${regex}" COMMAND ${run} ${prm})
  endforeach()
endfunction()

# perideal_variant_prm(NAME BASE from to [from to ...]): the parameter file
# BASE with each FROM replaced by its TO, in order, written to NAME.prm in the
# calling folder's build directory. A FROM that is not in the text stops the
# configuration: the variant would run the base deck unchanged.
function(perideal_variant_prm name base)
  file(READ ${base} text)
  set(pairs ${ARGN})
  list(LENGTH pairs n)
  math(EXPR last "${n} - 2")
  foreach(k RANGE 0 ${last} 2)
    math(EXPR next "${k} + 1")
    list(GET pairs ${k} from)
    list(GET pairs ${next} to)
    string(FIND "${text}" "${from}" at)
    if(at EQUAL -1)
      message(FATAL_ERROR "perideal_variant_prm(${name}): '${from}' is not in ${base}")
    endif()
    string(REPLACE "${from}" "${to}" text "${text}")
  endforeach()
  file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/${name}.prm "${text}")
endfunction()

# perideal_variant_error_test(NAME BASE REGEX re [NP n...] REPLACE from to
#                             [from to ...]): perideal_variant_prm(NAME BASE
# ...); pd_app on it must fail with a message matching "Error: re", on each
# rank count given (default 1).
function(perideal_variant_error_test name base)
  cmake_parse_arguments(V "" "REGEX" "NP;REPLACE" ${ARGN})
  if(NOT V_NP)
    set(V_NP 1)
  endif()
  perideal_variant_prm(${name} ${base} ${V_REPLACE})
  foreach(np ${V_NP})
    perideal_pd_app_command(run ${np})
    perideal_error_test(${name} ${np} REGEX "Error: ${V_REGEX}" COMMAND ${run} ${CMAKE_CURRENT_BINARY_DIR}/${name}.prm)
  endforeach()
endfunction()

# perideal_output_test(NAME NP [STDOUT re...] [SAME_AS file] [HINT text]
#                      [ABSENT glob...] [PRESENT glob...] COMMAND ...): COMMAND,
# run in a new empty directory, exits with 0; its standard output matches each
# STDOUT (extended, line by line) or equals SAME_AS (HINT: what to do if not);
# no file matches an ABSENT glob, some file each PRESENT glob. Runner mode 'output'.
function(perideal_output_test name np)
  cmake_parse_arguments(T "" "SAME_AS;HINT" "STDOUT;ABSENT;PRESENT;COMMAND" ${ARGN})
  set(checks)
  foreach(re ${T_STDOUT})
    list(APPEND checks --stdout ${re})
  endforeach()
  if(T_SAME_AS)
    list(APPEND checks --same-as ${T_SAME_AS})
  endif()
  if(T_HINT)
    list(APPEND checks --hint ${T_HINT})
  endif()
  foreach(glob ${T_ABSENT})
    list(APPEND checks --absent ${glob})
  endforeach()
  foreach(glob ${T_PRESENT})
    list(APPEND checks --present ${glob})
  endforeach()
  perideal_add_test(${perideal_test_group}.${name}.np${np} ${np} 120
    ${PERIDEAL_RUN} output ${checks} -- ${T_COMMAND})
endfunction()

# perideal_restart_test(NAME NP BASE_NAME PRM [SIGNAL sig | FIRST prm0]): pd_app
# on NP ranks on PRM to the end, then continued with --restart from its last
# checkpoint (with SIGNAL: from the checkpoint a run stopped by the signal
# wrote; with FIRST: from the checkpoint of PRM0, PRM's first solver alone): the globals CSV, the .pvd and the last step's pieces equal
# the uninterrupted run's byte for byte. Runner mode 'restart'.
function(perideal_restart_test name np base prm)
  cmake_parse_arguments(T "" "SIGNAL;FIRST" "" ${ARGN})
  perideal_pd_app_command(run ${np})
  set(signal)
  if(T_SIGNAL)
    set(signal --signal ${T_SIGNAL})
  elseif(T_FIRST)
    set(signal --first ${T_FIRST})
  endif()
  perideal_add_test(${perideal_test_group}.${name}.np${np} ${np} 180
    ${PERIDEAL_RUN} restart ${signal} ${base} ${run} ${prm})
endfunction()

# perideal_interrupt_test(NAME NP SIGNAL BASE_NAME PRM [STALLED_STDOUT]):
# pd_app on NP ranks on PRM, stopped by SIGNAL (TERM, INT, KILL) once its
# globals CSV output/BASE_NAME.globals.csv has rows; STALLED_STDOUT: once it
# is blocked writing to a standard output nobody reads. Runner mode 'interrupt'.
function(perideal_interrupt_test name np signal base prm)
  perideal_pd_app_command(run ${np})
  set(stalled)
  if("STALLED_STDOUT" IN_LIST ARGN)
    set(stalled --stalled-stdout)
  endif()
  perideal_add_test(${perideal_test_group}.${name}.np${np} ${np} 120
    ${PERIDEAL_RUN} interrupt ${stalled} ${signal} ${base} ${run} ${prm})
endfunction()

# perideal_check_tail(OPTIONS_VAR CHECK_VAR EXPECTED NUMDIFF_ARGS CHECK
# [REPORT_LINES]): what program and example tests append alike for the runner's
# check mode: --expected FILE (from this folder) with its numdiff arguments
# (--report-lines first with REPORT_LINES), and '--- CHECK' if there is one.
macro(perideal_check_tail options_var check_var expected numdiff_args check_command)
  if(${expected})
    if("${ARGN}" STREQUAL "REPORT_LINES")
      list(APPEND ${options_var} --report-lines)
    endif()
    list(APPEND ${options_var} --expected ${CMAKE_CURRENT_SOURCE_DIR}/${${expected}})
    foreach(a ${${numdiff_args}})
      list(APPEND ${options_var} --numdiff-arg ${a})
    endforeach()
  endif()
  set(${check_var})
  if(${check_command})
    set(${check_var} --- ${${check_command}})
  endif()
endmacro()

# perideal_program_test(NAME COMMAND <program and arguments>
#                       [EXPECT success|error] [REGEX re] [CHECK <command>]
#                       [EXPECTED file] [NUMDIFF_ARGS args]): the program
# (pd_app or a test program) under mpirun -np 1 and -np 2, in the work
# directory GROUP.NAME.npN of the build tree; its exit code as EXPECT
# (default success); its standard output and error together match REGEX
# (extended, over the whole text); CHECK then runs there and must exit with 0;
# its standard output (or the program's, without CHECK) equals the calling
# folder's EXPECTED under numdiff (default tolerances -a 1e-9 -r 1e-6). Both
# rank counts against the same file: 1 and 2 ranks agree. Runner mode 'check'.
function(perideal_program_test name)
  cmake_parse_arguments(T "" "EXPECT;REGEX;EXPECTED" "COMMAND;CHECK;NUMDIFF_ARGS" ${ARGN})
  if(NOT T_EXPECT)
    set(T_EXPECT success)
  endif()
  if(NOT T_NUMDIFF_ARGS)
    set(T_NUMDIFF_ARGS -q -a 1e-9 -r 1e-6)
  endif()
  foreach(np 1 2)
    set(test ${perideal_test_group}.${name}.np${np})
    set(options --workdir ${CMAKE_CURRENT_BINARY_DIR}/${test} --expect ${T_EXPECT})
    if(T_REGEX)
      list(APPEND options --regex ${T_REGEX})
    endif()
    perideal_check_tail(options check T_EXPECTED T_NUMDIFF_ARGS T_CHECK)
    perideal_add_test(${test} ${np} 300
      ${PERIDEAL_RUN} check ${options} -- ${PERIDEAL_MPIRUN} -np ${np} ${T_COMMAND} ${check})
  endforeach()
endfunction()

# perideal_example_test(NAME NP PRM <files> CSV <file> [REGEX re]
#                       [EXPECTED file] [NUMDIFF_ARGS args]
#                       [LAST_ROW_MIN column minimum ...] [CHECK command args]
#                       [FIXTURE name]): pd_app on NP ranks (mpirun) on the
# first parameter file with the others' settings applied (case.prm), in the
# work directory GROUP.NAME.npNP of the build tree. It exits with 0, its
# standard output matches REGEX, it writes CSV, whose last row has each
# column >= its minimum; CHECK then exits with 0; the set-up report's points,
# bonds and block lines followed by CHECK's standard output (or the CSV)
# equal EXPECTED under numdiff. FIXTURE: the test sets up that fixture.
# Runner mode 'check'.
function(perideal_example_test name np)
  cmake_parse_arguments(T "" "CSV;REGEX;EXPECTED;FIXTURE" "PRM;NUMDIFF_ARGS;LAST_ROW_MIN;CHECK" ${ARGN})
  set(test ${perideal_test_group}.${name}.np${np})
  set(options --workdir ${CMAKE_CURRENT_BINARY_DIR}/${test} --source-dir ${PROJECT_SOURCE_DIR} --csv ${T_CSV})
  foreach(prm ${T_PRM})
    list(APPEND options --prm ${prm})
  endforeach()
  if(T_REGEX)
    list(APPEND options --stdout-regex ${T_REGEX})
  endif()
  list(LENGTH T_LAST_ROW_MIN n)
  if(n GREATER 0)
    math(EXPR last "${n} - 1")
    foreach(i RANGE 0 ${last} 2)
      math(EXPR j "${i} + 1")
      list(GET T_LAST_ROW_MIN ${i} column)
      list(GET T_LAST_ROW_MIN ${j} minimum)
      list(APPEND options --last-row-min ${column} ${minimum})
    endforeach()
  endif()
  perideal_check_tail(options check T_EXPECTED T_NUMDIFF_ARGS T_CHECK REPORT_LINES)
  perideal_add_test(${test} ${np} 600
    ${PERIDEAL_RUN} check ${options} -- ${PERIDEAL_MPIRUN} -np ${np} ${PERIDEAL_PD_APP} case.prm ${check})
  if(T_FIXTURE)
    set_tests_properties(${test} PROPERTIES FIXTURES_SETUP ${T_FIXTURE})
  endif()
endfunction()
