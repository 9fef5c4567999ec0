#!/usr/bin/env bash
# expect_error.sh [-F] PATTERN COMMAND [ARGUMENTS...]
#
# Runs COMMAND and passes only if it fails cleanly with the expected message:
#   - the exit code is non-zero, not 126 or 127 (the command could not be
#     run) and not a crash (a signal gives 128 or more),
#   - standard error has a line starting with 'Error: ', and
#   - standard error matches PATTERN, an extended regular expression
#     (with -F: a fixed string).
# Prints the command's output either way, so that ctest --output-on-failure
# shows what happened.
set -uo pipefail

mode=-E
if [[ ${1:-} == -F ]]; then
  mode=-F
  shift
fi
if [[ $# -lt 2 ]]; then
  echo "usage: $0 [-F] PATTERN COMMAND [ARGUMENTS...]" >&2
  exit 2
fi
pattern=$1
shift

err=$(mktemp)
trap 'rm -f "$err"' EXIT
"$@" 2>"$err"
rc=$?
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
echo "PASS: exit code $rc and the expected message"
