#!/usr/bin/env bash
# error_line_whole.sh COMMAND...: COMMAND (pd_app, or mpirun -np N pd_app,
# on a parameter file it refuses) writes its 'Error: ...' line to standard
# error with one write() of the whole line, so that under mpirun no other
# line can land between 'Error: ' and its message. Traced with strace
# (exit 77, a skip, where strace is missing or may not trace).
set -uo pipefail
command -v strace >/dev/null && strace -qq -o /dev/null true 2>/dev/null ||
  { echo "SKIP: strace cannot trace here"; exit 77; }
trace=$(mktemp)
err=$(mktemp)
trap 'rm -f "$trace" "$err"' EXIT
strace -f -qq -e trace=write -e signal=none -s 65536 -o "$trace" "$@" >/dev/null 2>"$err"
rc=$?
echo "--- standard error (exit code $rc):"
cat "$err"
fail() {
  echo "--- the writes to standard error:"
  grep -E 'write\(2, ' "$trace" | head -20
  echo "FAIL: $*"
  exit 1
}
[[ $rc -ne 0 && $rc -lt 128 ]] || fail "exit code $rc, expected a clean error"
grep -q '^Error: ' "$err" || fail "no 'Error: ' line"
# A write(2, "Error: ...\n", N) = N of the whole line: it begins with
# 'Error: ', holds the message and ends with the newline.
grep -qE '^[0-9]+ +write\(2, "Error: [^"]{20,}\\n"' "$trace" ||
  fail "the 'Error: ' line is not written whole by one write()"
echo "PASS: the Error line is one write()"
