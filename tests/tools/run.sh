#!/usr/bin/env bash
# The test runner of the suite: runs pd_app (or a test program), directly or
# under mpirun, captures its standard output, standard error and exit code,
# and checks them. tests/tools/perideal_tests.cmake builds its command lines.
#
#   run.sh [--fifo PATH] MODE ARGUMENTS...
#
# --fifo PATH: first make the named pipe PATH (if it is not there yet): the
#   parameter file tests for a file that is not a regular file. Nothing ever
#   writes to the pipe, so a program that opens it for reading blocks forever;
#   the test's TIMEOUT catches that.
#
# MODE error [-v KIB] [-o REGEX] PATTERN COMMAND [ARGUMENTS...]
#   passes only if COMMAND fails cleanly with the expected message:
#   - the exit code is non-zero, not 126 or 127 (the command could not be
#     run) and not a crash (a signal gives 128 or more),
#   - standard error has a line starting with 'Error: ', and
#   - standard error matches PATTERN, an extended regular expression, line
#     by line as grep.
#   -v KIB: run COMMAND with its virtual memory limited to KIB kibibytes
#     (ulimit -v, RLIMIT_AS, inherited by mpirun's ranks): a scene too large
#     must be refused, not allocated.
#   -o REGEX: standard output must match REGEX too (extended; may be repeated).
#   -k PREPARE: a refused run changes no file. COMMAND runs in a new empty
#     directory after the shell text PREPARE (bash, there) has made the files
#     a user has there (data, an output folder, a checkpoint); after the run
#     every file and folder there must be as before: the same names and
#     types, the same bytes (SHA-256), none added or removed. Paths in
#     COMMAND and PREPARE should be absolute or relative to that directory.
#   -f KIB: COMMAND may write files of at most KIB kibibytes (ulimit -f,
#     SIGXFSZ ignored: a write beyond fails with EFBIG, as on a full disk).
#
# MODE output [CHECK...] -- COMMAND [ARGUMENTS...]
#   runs COMMAND in a new empty directory and passes only if it exits with 0
#   and every CHECK holds:
#     --stdout PATTERN   standard output matches the extended regular expression
#     --same-as FILE     standard output equals FILE byte for byte
#     --absent GLOB      no file matching GLOB (under the run directory) exists after the run
#     --present GLOB     a file matching GLOB exists after the run
#     --hint TEXT        printed after a failure: how to fix it
#   Paths in COMMAND should be absolute: the run directory is a fresh one.
#
# MODE interrupt [--stalled-stdout] SIGNAL BASE_NAME COMMAND [ARGUMENTS...]
#   runs COMMAND (pd_app, or mpirun -np N pd_app, on a long run whose Output
#   writes fields and globals into output/ under BASE_NAME) in a new empty
#   directory, waits until the globals CSV has a few rows, sends SIGNAL (TERM,
#   INT) to the process (to mpirun for a parallel run, as a user's Ctrl-C or a
#   batch system does) and passes only if the run stopped cleanly:
#   - it exited by itself within the time limit, with a non-zero code (pd_app
#     run directly: 128 + the signal),
#   - standard error has "Error: interrupted by SIG... at step N (t = ...):
#     the output holds steps up to N", standard output or error the summary
#     (standard error where standard output is not a file: mpirun's ranks),
#   - the .pvd lists exactly the steps that have a .pvtu, the last one N,
#   - every .pvtu's pieces exist, every .vtu is a piece of a .pvtu, and no
#     temporary file is left,
#   - the CSV has one row per .pvd step, the same steps.
#   SIGNAL KILL: SIGKILL to the process (to a rank under mpirun) at once, no
#   clean stop; then only the files are checked: written whole or not at all,
#   the .pvd and the .pvtu files and pieces as above (temporary files may stay,
#   and the last .pvtu may not be in the .pvd yet),
#   the CSV at most the .pvd's last step behind it, never ahead.
#   --stalled-stdout: COMMAND's standard output is a pipe that nobody reads
#   (as mpirun's terminal while it stops a job); the signal comes once the
#   run is blocked writing to it. Standard error must then hold the summary.
#   Bounded: 60 s for the first rows (and the block), 20 s for the stop.
#
# MODE restart [--signal SIGNAL | --first PRM0] BASE_NAME COMMAND [ARGUMENTS...] PRM
#   a checkpoint and its continuation equal the uninterrupted run. COMMAND
#   (pd_app, or mpirun -np N pd_app) on PRM (its last argument, whose Output
#   writes fields and globals into output/ under BASE_NAME) runs, in a new
#   empty directory:
#   1. to the end: the reference (kept as reference/);
#   2. without --signal, the reference's last checkpoint (PRM's
#      Output/Checkpoint/Frequency) is the start; with --signal, PRM runs
#      again and is stopped by SIGNAL once its CSV has 3 rows: it must exit
#      with the 'Error: interrupted' line and leave output/BASE_NAME.checkpoint;
#   3. COMMAND --restart <that checkpoint> PRM runs to the end and says
#      'Restarted from'; then its globals CSV, .pvd and the last step's .vtu
#      pieces must equal the reference's byte for byte.
#   With --first PRM0 (PRM0: PRM's first solver alone, Solver stages left
#   out, its checkpoint at its last step), step 2 runs PRM0 instead: a run
#   of solver stages equals the same solvers run by hand one after the other.
#   With --signal, before 3: the stop's checkpoint, with one byte of rank 0's
#   file flipped, must be refused with an Error naming the CRC-32 check.
#
# MODE check --workdir DIR [OPTIONS] -- COMMAND [ARGUMENTS...] [--- CHECK [ARGUMENTS...]]
#   runs COMMAND in DIR (emptied first), keeps its output in DIR/run.stdout
#   and DIR/run.stderr, then:
#     --expect success|error  the exit code is 0 (default) or not 0
#     --regex RE         standard output and error together match RE (an
#                        extended regular expression over the whole text: '.'
#                        and '[^x]' match a newline, '^' and '$' anchor at its
#                        ends)
#     --stdout-regex RE  the same for standard output alone
#     --prm FILE         (repeatable) DIR/case.prm is the first FILE with the
#                        'set' lines of the others applied in order
#                        (merge_prm.py), @PERIDEAL_SOURCE_DIR@ replaced by
#                        --source-dir; COMMAND names it case.prm
#     --csv FILE         the globals CSV the run writes (relative to DIR): it
#                        must exist
#     --last-row-min COLUMN MIN  (repeatable) the last row of the CSV has
#                        COLUMN >= MIN
#     CHECK              a command run in DIR after COMMAND; must exit with 0
#     --expected FILE    DIR/compared.txt must equal FILE under numdiff
#                        ($PERIDEAL_NUMDIFF) with the --numdiff-arg
#                        arguments (repeatable): the standard output of CHECK,
#                        else the CSV (--csv), else the standard output of
#                        COMMAND; with --report-lines preceded by the set-up
#                        report's points, bonds and block lines (the part of
#                        the report that does not depend on the rank count)
# Each mode prints what it ran and saw, so that ctest --output-on-failure
# shows what happened, and ends with a PASS line or a FAIL line and exit 1.
set -uo pipefail

usage() {
  sed -n '2,/^set -uo/p' "${BASH_SOURCE[0]}" | sed '$d' | sed 's/^# \{0,1\}//' >&2
  exit 2
}

# ----------------------------------------------------------------- error
mode_error() {
  local limit= file_limit= stdout_patterns=() prepare= keep=0
  while [[ $# -gt 0 ]]; do
    case $1 in
      -v) limit=$2; shift 2 ;;
      -f) file_limit=$2; shift 2 ;;
      -o) stdout_patterns+=("$2"); shift 2 ;;
      -k) prepare=$2; keep=1; shift 2 ;;
      *) break ;;
    esac
  done
  [[ $# -ge 2 ]] || usage
  local pattern=$1
  shift

  err=$(mktemp)
  out=$(mktemp)
  work=
  trap 'rm -f "$err" "$out"; [[ -z $work ]] || rm -rf "$work"' EXIT
  # Every entry under the directory: its type, name and, for a file, SHA-256.
  snapshot() {
    (cd "$work" && find . -mindepth 1 -printf '%y %p\n' | LC_ALL=C sort &&
      find . -type f -exec sha256sum {} + | LC_ALL=C sort -k 2)
  }
  local before=
  if [[ $keep -eq 1 ]]; then
    work=$(mktemp -d "${TMPDIR:-/tmp}/unchanged.XXXXXX")
    (cd "$work" && bash -e -c "$prepare") >"$out" 2>"$err" ||
      { cat "$out" "$err"; echo "FAIL: the preparation failed: $prepare"; exit 1; }
    before=$(snapshot)
    echo "--- files before the run:"
    echo "$before" | grep -v '^[0-9a-f]\{64\} '
  fi
  (
    [[ -z $work ]] || cd "$work" || exit 2
    [[ -z $limit ]] || ulimit -v "$limit" || exit 2
    if [[ -n $file_limit ]]; then
      trap '' XFSZ
      ulimit -f "$file_limit" || exit 2
    fi
    exec "$@"
  ) >"$out" 2>"$err"
  local rc=$?
  echo "--- standard output:"
  cat "$out"
  echo "--- standard error (exit code $rc):"
  cat "$err"

  fail() {
    echo "FAIL: $*"
    exit 1
  }
  [[ $rc -ne 0 ]] || fail "exit code 0, expected an error"
  [[ $rc -ne 126 && $rc -ne 127 ]] || fail "exit code $rc: the command could not be run"
  [[ $rc -lt 128 ]] || fail "exit code $rc: a crash or a signal, not a clean error"
  grep -q '^Error: ' "$err" || fail "no line starting with 'Error: ' on standard error"
  grep -q -E -e "$pattern" "$err" || fail "standard error does not match: $pattern"
  local p
  for p in ${stdout_patterns[@]+"${stdout_patterns[@]}"}; do
    grep -q -E -e "$p" "$out" || fail "standard output does not match: $p"
  done
  if [[ $keep -eq 1 ]]; then
    local after
    after=$(snapshot)
    [[ $after == "$before" ]] ||
      { diff <(echo "$before") <(echo "$after"); fail "the files differ after the refused run (above: < before, > after)"; }
    echo "PASS: exit code $rc, the expected message, every file as before the run"
    return
  fi
  echo "PASS: exit code $rc and the expected message"
}

# ---------------------------------------------------------------- output
mode_output() {
  local stdout_patterns=() same_as="" hint="" absent=() present=()
  while [[ $# -gt 0 && $1 != -- ]]; do
    case $1 in
      --stdout) stdout_patterns+=("$2"); shift 2 ;;
      --same-as) same_as=$2; shift 2 ;;
      --hint) hint=$2; shift 2 ;;
      --absent) absent+=("$2"); shift 2 ;;
      --present) present+=("$2"); shift 2 ;;
      *) echo "$0: unknown check '$1'" >&2; exit 2 ;;
    esac
  done
  [[ $# -ge 2 ]] || usage
  shift

  dir=$(mktemp -d)
  trap 'rm -rf "$dir"' EXIT
  (cd "$dir" && "$@" >"$dir/.stdout" 2>"$dir/.stderr")
  local rc=$?
  echo "--- standard output (exit code $rc):"
  cat "$dir/.stdout"
  echo "--- standard error:"
  cat "$dir/.stderr"

  local failed=0
  fail() {
    echo "FAIL: $*"
    failed=1
  }
  [[ $rc -eq 0 ]] || fail "exit code $rc, expected 0"
  local p g found
  for p in ${stdout_patterns[@]+"${stdout_patterns[@]}"}; do
    grep -q -E -e "$p" "$dir/.stdout" || fail "standard output does not match: $p"
  done
  if [[ -n $same_as ]]; then
    cmp -s "$same_as" "$dir/.stdout" ||
      { fail "standard output differs from $same_as:"; diff "$same_as" "$dir/.stdout" | head -40; }
  fi
  shopt -s nullglob globstar
  for g in ${absent[@]+"${absent[@]}"}; do
    found=("$dir"/$g)
    [[ ${#found[@]} -eq 0 ]] || fail "files that should not exist: ${found[*]#"$dir"/}"
  done
  for g in ${present[@]+"${present[@]}"}; do
    found=("$dir"/$g)
    [[ ${#found[@]} -gt 0 ]] || fail "no file matches $g"
  done
  if [[ $failed -ne 0 ]]; then
    [[ -z $hint ]] || echo "$hint"
    exit 1
  fi
  echo "PASS"
}

# enter_scratch NAME: cd into a new temporary directory, removed at exit
# together with the background run $pid, if one is still going.
enter_scratch() {
  run=$(mktemp -d "${TMPDIR:-/tmp}/$1.XXXXXX")
  pid=
  cleanup() {
    [[ -n $pid ]] && kill -KILL "$pid" 2>/dev/null
    rm -rf "$run"
  }
  trap cleanup EXIT
  cd "$run" || exit 2
}

# ------------------------------------------------------------- interrupt
mode_interrupt() {
  local stalled=
  [[ ${1:-} == --stalled-stdout ]] && { stalled=1; shift; }
  [[ $# -ge 3 ]] || usage
  local signal=$1 base=$2
  shift 2

  enter_scratch interrupt
  fail() {
    echo "--- standard output (tail):"
    tail -n 30 "$run/out.txt" 2>/dev/null
    echo "--- standard error:"
    cat "$run/err.txt"
    echo "--- files:"
    ls "$run/output" 2>/dev/null | tr '\n' ' '
    echo
    echo "FAIL: $*"
    exit 1
  }

  if [[ -n $stalled ]]; then
    # Held open for reading and writing, never read: writes block once the
    # pipe's 64 KiB are full.
    mkfifo stdout.fifo
    exec 3<>stdout.fifo
    "$@" >stdout.fifo 2>err.txt &
  else
    "$@" >out.txt 2>err.txt &
  fi
  pid=$!
  local csv=output/$base.globals.csv i rc
  for ((i = 0; i < 600; ++i)); do
    [[ -f $csv && $(wc -l <"$csv") -ge 3 ]] && break
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  # Blocked in write() on standard output: system call write (1 on x86_64,
  # 64 on aarch64) on descriptor 1.
  blocked_on_stdout() {
    local nr fd
    read -r nr fd _ <"/proc/$pid/syscall" 2>/dev/null || return 1
    [[ $fd == 0x1 && ($nr == 1 || $nr == 64) ]]
  }
  if [[ -n $stalled ]]; then
    for ((i = 0; i < 600; ++i)); do
      blocked_on_stdout && break
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.1
    done
  fi
  if ! kill -0 "$pid" 2>/dev/null; then
    wait "$pid"
    rc=$?
    pid=
    fail "the run ended before the signal (exit code $rc)"
  fi
  [[ -f $csv && $(wc -l <"$csv") -ge 3 ]] || fail "no globals rows after 60 s"
  [[ -z $stalled ]] || blocked_on_stdout || fail "not blocked on its standard output after 60 s"
  local target=$pid
  [[ $signal == KILL && $(basename "$1") != pd_app ]] && target=$(pgrep -P "$pid" | tail -n 1)
  kill -"$signal" "$target"
  for ((i = 0; i < 200; ++i)); do
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  if kill -0 "$pid" 2>/dev/null; then
    fail "still running 20 s after SIG$signal"
  fi
  wait "$pid"
  rc=$?
  pid=
  echo "exit code $rc after SIG$signal"
  if [[ -n $stalled ]]; then
    timeout 1 cat <&3 >out.txt
    exec 3>&-
  fi

  [[ $rc -ne 0 ]] || fail "exit code 0"
  # The steps the .pvd lists, the .pvtu files there are and the CSV rows (in output/).
  read_steps() {
    pvd_steps=$(grep -o "file=\"${base}_[0-9]*\.pvtu\"" "$base.pvd" | sed -E 's/.*_0*([0-9]+)\.pvtu"/\1/' | sort -n | tr '\n' ' ')
    pvtu_steps=$(ls "${base}"_*.pvtu | sed -E 's/.*_0*([0-9]+)\.pvtu/\1/' | sort -n | tr '\n' ' ')
    csv_steps=$(tail -n +2 "$base.globals.csv" | cut -d, -f1 | sort -n | tr '\n' ' ')
    echo ".pvd steps:  $pvd_steps"
    echo ".pvtu steps: $pvtu_steps"
    echo "CSV steps:   $csv_steps"
  }
  local pieces p vtus
  if [[ $signal == KILL ]]; then
    cd output || fail "no output directory"
    rm -f ./*.tmp
    read_steps
    # A kill between a step's .pvtu and its .pvd record leaves that one .pvtu
    # (complete, with its pieces) not yet listed: the .pvd is never ahead.
    [[ $pvd_steps == "$pvtu_steps" || "$pvd_steps$(awk '{print $NF}' <<<"$pvtu_steps") " == "$pvtu_steps" ]] ||
      fail "the .pvd steps differ from the .pvtu files (more than the last .pvtu not yet listed)"
    [[ $csv_steps == "$pvd_steps" || "$csv_steps$(awk '{print $NF}' <<<"$pvd_steps") " == "$pvd_steps" ]] ||
      fail "the CSV steps are not those of the .pvd (or one behind)"
    pieces=$(grep -ho 'Source="[^"]*"' ./*.pvtu | sed -E 's/Source="(.*)"/\1/' | sort)
    for p in $pieces; do
      [[ -s $p ]] || fail "piece $p of a .pvtu is missing"
    done
    vtus=$(ls ./*.vtu | sed 's|^\./||' | sort)
    # A kill after a step's pieces got their names and before its .pvtu was
    # written leaves that one step's pieces (whole) not yet listed.
    local extra stems
    extra=$(comm -23 <(echo "$vtus") <(echo "$pieces"))
    if [[ -n $extra ]]; then
      stems=$(sed -E 's/\.[0-9]{4}\.vtu$//' <<<"$extra" | sort -u)
      [[ $(wc -l <<<"$stems") == 1 && ! -e "$stems.pvtu" ]] ||
        fail "a .vtu that no .pvtu lists, of more than the step being written: $(tr '\n' ' ' <<<"$extra")"
      echo "pieces of the step being written, not yet listed: $(tr '\n' ' ' <<<"$extra")"
    fi
    echo "PASS: killed; the files written consistent"
    exit 0
  fi
  local expected name
  if [[ $(basename "$1") == pd_app ]]; then
    expected=$((128 + $(kill -l "$signal")))
    [[ $rc -eq $expected ]] || fail "exit code $rc, expected $expected (128 + SIG$signal)"
    name="SIG$signal"
  else
    name="SIG(TERM|INT)" # mpirun passes SIGTERM on to the ranks for both
  fi
  local line step upto last
  line=$(grep -E "^Error: interrupted by $name at step [0-9]+ \(t = [^)]*\): the output holds steps up to [0-9]+$" err.txt)
  [[ -n $line ]] || fail "no 'Error: interrupted by $name at step N ...' line on standard error"
  [[ $(grep -c '^Error: ' err.txt) -eq 1 ]] || fail "more than one Error line"
  step=$(sed -E 's/.* at step ([0-9]+) .*/\1/' <<<"$line")
  upto=$(sed -E 's/.*steps up to ([0-9]+)$/\1/' <<<"$line")
  [[ $step -eq $upto ]] || fail "stopped at step $step, output up to $upto"
  if [[ -n $stalled ]]; then
    grep -q '^PeriDeal summary' err.txt || fail "no summary on standard error (standard output blocked)"
  else
    grep -q '^PeriDeal summary' out.txt err.txt || fail "no summary on standard output or error"
  fi

  cd output || fail "no output directory"
  ls *.tmp >/dev/null 2>&1 && fail "temporary files left: $(ls *.tmp)"
  read_steps
  [[ $pvd_steps == "$pvtu_steps" ]] || fail "the .pvd steps differ from the .pvtu files"
  [[ $csv_steps == "$pvd_steps" ]] || fail "the CSV steps differ from the .pvd steps"
  [[ $(wc -w <<<"$pvd_steps") -ge 3 ]] || fail "fewer than 3 output steps"
  last=$(awk '{print $NF}' <<<"$pvd_steps")
  [[ $last -eq $step ]] || fail "the last output step $last is not the step of the stop $step"
  pieces=$(grep -ho 'Source="[^"]*"' ./*.pvtu | sed -E 's/Source="(.*)"/\1/' | sort)
  for p in $pieces; do
    [[ -s $p ]] || fail "piece $p of a .pvtu is missing"
  done
  vtus=$(ls ./*.vtu | sed 's|^\./||' | sort)
  [[ $vtus == "$pieces" ]] || fail "a .vtu that no .pvtu lists: $(comm -23 <(echo "$vtus") <(echo "$pieces") | tr '\n' ' ')"
  echo "PASS: stopped at step $step on SIG$signal, exit code $rc, the output consistent"
}

# ----------------------------------------------------------------- restart
mode_restart() {
  local signal= first=
  [[ ${1:-} == --signal ]] && { signal=$2; shift 2; }
  [[ ${1:-} == --first ]] && { first=$2; shift 2; }
  [[ $# -ge 3 ]] || usage
  local base=$1
  shift
  local prm=${*: -1}
  local command=("${@:1:$#-1}")
  enter_scratch restart
  fail() {
    for f in out.txt err.txt; do
      [[ -f $f ]] && { echo "--- $f (tail):"; tail -n 20 "$f"; }
    done
    echo "FAIL: $*"
    exit 1
  }
  local rc i csv=output/$base.globals.csv checkpoint
  "${command[@]}" "$prm" >out.txt 2>err.txt || fail "the uninterrupted run failed (exit code $?)"
  if [[ -n $first ]]; then
    mv output reference
    "${command[@]}" "$first" >first.out 2>first.err || fail "the run of the first solver alone failed"
    [[ -f output/$base.checkpoint/checkpoint.txt ]] || fail "the first solver's run wrote no checkpoint"
    mv output/$base.checkpoint checkpoint
    checkpoint=checkpoint
    echo "the first solver's run: checkpoint of step $(sed -n 's/^step //p' checkpoint/checkpoint.txt)"
    rm -rf output
  elif [[ -z $signal ]]; then
    [[ -f output/$base.checkpoint/checkpoint.txt ]] || fail "the run wrote no checkpoint"
    mv output/$base.checkpoint checkpoint
    checkpoint=checkpoint
    echo "the run's last checkpoint: step $(sed -n 's/^step //p' checkpoint/checkpoint.txt)"
    mv output reference
  else
    mv output reference
    "${command[@]}" "$prm" >out.txt 2>err.txt &
    pid=$!
    for ((i = 0; i < 600; ++i)); do
      [[ -f $csv && $(wc -l <"$csv") -ge 3 ]] && break
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.05
    done
    kill -0 "$pid" 2>/dev/null || fail "the run ended before the signal"
    kill -"$signal" "$pid"
    for ((i = 0; i < 400; ++i)); do
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.05
    done
    kill -0 "$pid" 2>/dev/null && fail "still running 20 s after SIG$signal"
    wait "$pid"
    rc=$?
    pid=
    [[ $rc -ne 0 ]] || fail "exit code 0 after SIG$signal"
    grep -qE '^Error: interrupted by SIG[A-Z]+ at step [0-9]+' err.txt || fail "no 'Error: interrupted' line"
    checkpoint=output/$base.checkpoint
    [[ -f $checkpoint/checkpoint.txt ]] || fail "the stop left no checkpoint"
    echo "stopped by SIG$signal; checkpoint of step $(sed -n 's/^step //p' $checkpoint/checkpoint.txt)"
    # A damaged checkpoint is refused, and names what is wrong.
    cp -r "$checkpoint" damaged
    local byte
    byte=$(od -An -tu1 -j100 -N1 damaged/rank-0000.bin | tr -d ' ')
    printf "\\x$(printf %02x $((byte ^ 255)))" | dd of=damaged/rank-0000.bin bs=1 seek=100 conv=notrunc status=none
    if "${command[@]}" --restart damaged "$prm" >damaged.out 2>damaged.err; then
      fail "a checkpoint with a flipped byte was accepted"
    fi
    grep -q "^Error: --restart 'damaged': 'damaged/rank-0000.bin' fails its CRC-32 check" damaged.err ||
      { cat damaged.err; fail "no CRC-32 error for the damaged checkpoint"; }
  fi
  if [[ -f reference/$base.e && ! -f output/$base.e ]]; then
    # Output/Field format = exodus: a continued run goes on in its file as
    # it stands in the output folder. Here it gets the uninterrupted run's
    # (every file of the series <base>.e, <base>.e-s0002, ... whose mesh
    # changed) with every step after the checkpoint spoilt (NaN), which the
    # continued run must write again.
    mkdir -p output && cp reference/"$base".e reference/"$base".e-s* output/ 2>/dev/null
    [[ -f output/$base.e ]] || fail "cannot copy reference/$base.e"
    "$PERIDEAL_PYTHON" - "$(sed -n 's/^time //p' "$checkpoint/checkpoint.txt")" output/"$base".e output/"$base".e-s* <<'EOF' ||
import sys, netCDF4
after = float.fromhex(sys.argv[1])
spoilt = 0
for path in sys.argv[2:]:
    if path.endswith("-s*"):
        continue  # no series
    nc = netCDF4.Dataset(path, "a")
    steps = [k for k, t in enumerate(nc.variables["time_whole"][:]) if t > after]
    for name, v in nc.variables.items():
        if name.startswith("vals_") or name == "time_whole":
            for k in steps:
                v[k] = float("nan")
    nc.close()
    spoilt += len(steps)
print("the Exodus files' %d steps after the checkpoint spoilt" % spoilt)
sys.exit(0 if spoilt else 1)
EOF
      fail "no Exodus step after the checkpoint to spoil"
  fi
  "${command[@]}" --restart "$checkpoint" "$prm" >out.txt 2>err.txt || fail "the continued run failed"
  grep -q "^Restarted from '$checkpoint': step [0-9]*" out.txt || fail "no 'Restarted from' line"
  cmp "reference/$base.globals.csv" "$csv" || fail "the continued globals CSV differs from the uninterrupted run's"
  local last pieces p
  if [[ -f reference/$base.e ]]; then
    pieces=$(cd reference && ls "$base".e "$base".e-s* 2>/dev/null)
    for p in $pieces; do
      cmp "reference/$p" "output/$p" || fail "the continued Exodus file $p differs from the uninterrupted run's"
    done
    [[ $(cd output && ls "$base".e "$base".e-s* 2>/dev/null | wc -l) -eq $(echo $pieces | wc -w) ]] ||
      fail "the continued run wrote other Exodus files than the uninterrupted run"
    echo "PASS: continued from $checkpoint: $(($(wc -l <"$csv") - 1)) globals rows and the $(echo $pieces | wc -w) Exodus files equal the uninterrupted run's byte for byte"
    return
  fi
  if [[ -f reference/$base.xdmf ]]; then
    # Output/Field format = hdf5: the series and every file the continued run
    # wrote (its steps' .h5; the mesh file stays the first run's).
    cmp "reference/$base.xdmf" "output/$base.xdmf" || fail "the continued .xdmf differs from the uninterrupted run's"
    pieces=$(cd output && ls ./*.h5 2>/dev/null)
    [[ -n $pieces ]] || fail "the continued run wrote no .h5 file"
    for p in $pieces; do
      cmp "reference/$p" "output/$p" || fail "the continued run's $p differs"
    done
    echo "PASS: continued from $checkpoint: $(($(wc -l <"$csv") - 1)) globals rows, the .xdmf and the $(echo $pieces | wc -w) .h5 files written after the restart equal the uninterrupted run's byte for byte"
    return
  fi
  # (deal.II's .pvd carries the time of its writing in a comment)
  cmp <(grep -v 'generated by the deal.II library' "reference/$base.pvd") \
    <(grep -v 'generated by the deal.II library' "output/$base.pvd") ||
    fail "the continued .pvd differs from the uninterrupted run's"
  last=$(grep -o "file=\"[^\"]*\.pvtu\"" "reference/$base.pvd" | tail -n 1 | sed -E 's/file="(.*)"/\1/')
  [[ -n $last ]] || fail "no .pvtu in the reference's .pvd"
  pieces=$(grep -o 'Source="[^"]*"' "reference/$last" | sed -E 's/Source="(.*)"/\1/')
  for p in $pieces; do
    cmp "reference/$p" "output/$p" || fail "the last step's piece $p differs"
  done
  echo "PASS: continued from $checkpoint: $(($(wc -l <"$csv") - 1)) globals rows, the .pvd and the last step's pieces ($last) equal the uninterrupted run's byte for byte"
}

# ----------------------------------------------------------------- check
mode_check() {
  local workdir= expect=success regex= has_regex=0 stdout_regex= has_stdout_regex=0 prm=() source_dir=
  local csv= last_min=() expected= numdiff_args=() report_lines=0
  while [[ $# -gt 0 && $1 != -- ]]; do
    case $1 in
      --workdir) workdir=$2; shift 2 ;;
      --expect) expect=$2; shift 2 ;;
      --regex) regex=$2; has_regex=1; shift 2 ;;
      --stdout-regex) stdout_regex=$2; has_stdout_regex=1; shift 2 ;;
      --prm) prm+=("$2"); shift 2 ;;
      --source-dir) source_dir=$2; shift 2 ;;
      --csv) csv=$2; shift 2 ;;
      --last-row-min) last_min+=("$2" "$3"); shift 3 ;;
      --expected) expected=$2; shift 2 ;;
      --numdiff-arg) numdiff_args+=("$2"); shift 2 ;;
      --report-lines) report_lines=1; shift ;;
      *) echo "$0: unknown option '$1'" >&2; exit 2 ;;
    esac
  done
  [[ $# -ge 2 && -n $workdir ]] || usage
  [[ $expect == success || $expect == error ]] || usage
  shift
  local command=() check=()
  while [[ $# -gt 0 && $1 != --- ]]; do
    command+=("$1")
    shift
  done
  if [[ $# -gt 0 ]]; then
    shift
    check=("$@")
    [[ ${#check[@]} -gt 0 ]] || usage
  fi

  fail() {
    echo "FAIL: $*"
    exit 1
  }
  rm -rf "$workdir"
  mkdir -p "$workdir" || fail "cannot make $workdir"
  cd "$workdir" || fail "cannot enter $workdir"

  # pd_app refuses a key or subsection given twice: the later files are
  # overlays merged into the first (merge_prm.py), not appended.
  if [[ ${#prm[@]} -gt 0 ]]; then
    [[ -n ${PERIDEAL_PYTHON:-} ]] || fail "PERIDEAL_PYTHON is not set (needed to merge ${prm[*]})"
    "$PERIDEAL_PYTHON" "$(dirname "${BASH_SOURCE[0]}")/merge_prm.py" --source-dir "$source_dir" "${prm[@]}" >case.prm ||
      fail "merge_prm.py ${prm[*]} failed"
  fi

  "${command[@]}" >run.stdout 2>run.stderr
  local rc=$?
  echo "---- ${command[*]}"
  cat run.stdout
  if [[ -s run.stderr ]]; then
    echo "---- stderr"
    cat run.stderr
  fi
  echo "---- exit code $rc"
  if [[ $expect == success ]]; then
    [[ $rc -eq 0 ]] || fail "expected success, got exit code $rc"
  else
    [[ $rc -ne 0 ]] || fail "expected an error exit code, got $rc"
  fi
  local text
  if [[ $has_regex -eq 1 ]]; then
    text=$(cat run.stdout run.stderr; echo .)
    [[ ${text%.} =~ $regex ]] || fail "the output does not match '$regex'"
  fi
  if [[ $has_stdout_regex -eq 1 ]]; then
    text=$(cat run.stdout; echo .)
    [[ ${text%.} =~ $stdout_regex ]] || fail "the output does not match '$stdout_regex'"
  fi

  if [[ -n $csv ]]; then
    [[ -f $csv ]] || fail "the run wrote no $workdir/$csv"
    local k value
    for ((k = 0; k < ${#last_min[@]}; k += 2)); do
      value=$(awk -F, -v column="${last_min[k]}" '
        NR == 1 { for (c = 1; c <= NF; ++c) if ($c == column) at = c }
        { last = $0 }
        END { if (!at) exit 1; n = split(last, f, ","); print f[at] }' "$csv") ||
        fail "$csv has no column '${last_min[k]}'"
      awk -v v="$value" -v m="${last_min[k + 1]}" 'BEGIN { exit !(v + 0 >= m + 0) }' ||
        fail "${last_min[k]} = $value in the last row of $csv, expected >= ${last_min[k + 1]}"
      echo "---- last row: ${last_min[k]} = $value >= ${last_min[k + 1]}"
    done
  fi

  if [[ ${#check[@]} -gt 0 ]]; then
    "${check[@]}" >check.stdout 2>check.stderr
    local check_rc=$?
    echo "---- ${check[*]}"
    cat check.stdout check.stderr
    [[ $check_rc -eq 0 ]] || fail "the check failed (exit code $check_rc)"
  fi

  if [[ -n $expected ]]; then
    [[ -n ${PERIDEAL_NUMDIFF:-} ]] || fail "PERIDEAL_NUMDIFF is not set"
    {
      if [[ $report_lines -eq 1 ]]; then
        # The set-up report ends with the first line of the time integration.
        awk '/^(Time integration|Quasistatic:|Newmark:)/ && NR > 1 { exit }
             /^  (points|bonds|block \047.*\047):/ { print }' run.stdout |
          sed -E 's/ \(nonlocal ghosts: [0-9]+\)//g'
      fi
      if [[ ${#check[@]} -gt 0 ]]; then
        cat check.stdout
      elif [[ -n $csv ]]; then
        cat "$csv"
      else
        cat run.stdout
      fi
    } >compared.txt
    local diff_out
    diff_out=$("$PERIDEAL_NUMDIFF" "${numdiff_args[@]}" "$expected" compared.txt) ||
      fail "numdiff ${numdiff_args[*]}: $workdir/compared.txt differs from $expected"$'\n'"$diff_out"
    echo "---- numdiff ${numdiff_args[*]} against $expected: equal"
  fi
  echo "PASS"
}

if [[ ${1:-} == --fifo ]]; then
  [[ $# -ge 3 ]] || usage
  # The 1- and 2-rank tests may run at once: either may make the pipe.
  mkfifo "$2" 2>/dev/null || [[ -p $2 ]] || { echo "cannot make the FIFO $2" >&2; exit 2; }
  shift 2
fi
[[ $# -ge 1 ]] || usage
mode=$1
shift
case $mode in
  error) mode_error "$@" ;;
  output) mode_output "$@" ;;
  interrupt) mode_interrupt "$@" ;;
  restart) mode_restart "$@" ;;
  check) mode_check "$@" ;;
  *) usage ;;
esac
