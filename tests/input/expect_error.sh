#!/usr/bin/env bash
# expect_error.sh [-F] [-v KIB] [-o REGEX] PATTERN COMMAND [ARGUMENTS...]
#
# Runs COMMAND and passes only if it fails cleanly with the expected message:
#   - the exit code is non-zero, not 126 or 127 (the command could not be
#     run) and not a crash (a signal gives 128 or more),
#   - standard error has a line starting with 'Error: ', and
#   - standard error matches PATTERN, an extended regular expression
#     (with -F: a fixed string).
# -v KIB: run COMMAND with its virtual memory limited to KIB kibibytes
#     (ulimit -v, RLIMIT_AS, inherited by mpirun's ranks): a scene too large
#     must be refused, not allocated.
# -o REGEX: standard output must match REGEX too (extended; may be repeated).
# Prints the command's output either way, so that ctest --output-on-failure
# shows what happened.
set -uo pipefail

mode=-E
limit=
stdout_patterns=()
while [[ $# -gt 0 ]]; do
  case $1 in
    -F) mode=-F; shift ;;
    -v) limit=$2; shift 2 ;;
    -o) stdout_patterns+=("$2"); shift 2 ;;
    *) break ;;
  esac
done
if [[ $# -lt 2 ]]; then
  echo "usage: $0 [-F] PATTERN COMMAND [ARGUMENTS...]" >&2
  exit 2
fi
pattern=$1
shift

err=$(mktemp)
out=$(mktemp)
trap 'rm -f "$err" "$out"' EXIT
if [[ -n $limit ]]; then
  (ulimit -v "$limit" && exec "$@") >"$out" 2>"$err"
else
  "$@" >"$out" 2>"$err"
fi
rc=$?
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
grep -q $mode -e "$pattern" "$err" || fail "standard error does not match: $pattern"
for p in ${stdout_patterns[@]+"${stdout_patterns[@]}"}; do
  grep -q -E -e "$p" "$out" || fail "standard output does not match: $p"
done
echo "PASS: exit code $rc and the expected message"
