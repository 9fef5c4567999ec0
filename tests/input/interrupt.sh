#!/usr/bin/env bash
# interrupt.sh SIGNAL BASE_NAME COMMAND [ARGUMENTS...]
#
# Runs COMMAND (pd_app, or mpirun -np N pd_app, on a long run whose Output
# writes fields and globals into output/ under BASE_NAME) in a new empty
# directory, waits until the globals CSV has a few rows, sends SIGNAL (TERM,
# INT) to the process (to mpirun for a parallel run, as a user's Ctrl-C or a
# batch system does) and passes only if the run stopped cleanly:
#   - it exited by itself within the time limit, with a non-zero code (pd_app
#     run directly: 128 + the signal),
#   - standard error has "Error: interrupted by SIG... at step N (t = ...):
#     the output holds steps up to N", standard output the summary,
#   - the .pvd lists exactly the steps that have a .pvtu, the last one N,
#   - every .pvtu's pieces exist, every .vtu is a piece of a .pvtu, and no
#     temporary file is left,
#   - the CSV has one row per .pvd step, the same steps.
# SIGNAL KILL: SIGKILL to the process (to a rank under mpirun) at once, no
# clean stop; then only the files are checked: written whole or not at all,
# the .pvd and the .pvtu files and pieces as above (temporary files may stay,
# and the last .pvtu may not be in the .pvd yet),
# the CSV at most the .pvd's last step behind it, never ahead.
# Bounded: 60 s for the first rows, 20 s for the stop.
set -uo pipefail

if [[ $# -lt 3 ]]; then
  echo "usage: $0 SIGNAL BASE_NAME COMMAND [ARGUMENTS...]" >&2
  exit 2
fi
signal=$1
base=$2
shift 2

run=$(mktemp -d "${TMPDIR:-/tmp}/interrupt.XXXXXX")
pid=
cleanup() {
  [[ -n $pid ]] && kill -KILL "$pid" 2>/dev/null
  rm -rf "$run"
}
trap cleanup EXIT
cd "$run" || exit 2
fail() {
  echo "--- standard output (tail):"
  tail -n 30 "$run/out.txt"
  echo "--- standard error:"
  cat "$run/err.txt"
  echo "--- files:"
  ls "$run/output" 2>/dev/null | tr '\n' ' '
  echo
  echo "FAIL: $*"
  exit 1
}

"$@" >out.txt 2>err.txt &
pid=$!
csv=output/$base.globals.csv
for ((i = 0; i < 600; ++i)); do
  [[ -f $csv && $(wc -l <"$csv") -ge 3 ]] && break
  kill -0 "$pid" 2>/dev/null || break
  sleep 0.1
done
if ! kill -0 "$pid" 2>/dev/null; then
  wait "$pid"
  rc=$?
  pid=
  fail "the run ended before the signal (exit code $rc)"
fi
[[ -f $csv && $(wc -l <"$csv") -ge 3 ]] || fail "no globals rows after 60 s"
target=$pid
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
  [[ $vtus == "$pieces" ]] || fail "a .vtu that no .pvtu lists"
  echo "PASS: killed; the files written consistent"
  exit 0
fi
if [[ $(basename "$1") == pd_app ]]; then
  expected=$((128 + $(kill -l "$signal")))
  [[ $rc -eq $expected ]] || fail "exit code $rc, expected $expected (128 + SIG$signal)"
  name="SIG$signal"
else
  name="SIG(TERM|INT)" # mpirun passes SIGTERM on to the ranks for both
fi
line=$(grep -E "^Error: interrupted by $name at step [0-9]+ \(t = [^)]*\): the output holds steps up to [0-9]+$" err.txt)
[[ -n $line ]] || fail "no 'Error: interrupted by $name at step N ...' line on standard error"
[[ $(grep -c '^Error: ' err.txt) -eq 1 ]] || fail "more than one Error line"
step=$(sed -E 's/.* at step ([0-9]+) .*/\1/' <<<"$line")
upto=$(sed -E 's/.*steps up to ([0-9]+)$/\1/' <<<"$line")
[[ $step -eq $upto ]] || fail "stopped at step $step, output up to $upto"
grep -q '^PeriDeal summary' out.txt || fail "no summary on standard output"

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
