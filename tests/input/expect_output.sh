#!/usr/bin/env bash
# expect_output.sh [CHECK...] -- COMMAND [ARGUMENTS...]
#
# Runs COMMAND in a new empty directory and passes only if it exits with 0 and
# every CHECK holds:
#   --stdout PATTERN   standard output matches the extended regular expression
#   --same-as FILE     standard output equals FILE byte for byte
#   --absent GLOB      no file matching GLOB (under the run directory) exists after the run
#   --present GLOB     a file matching GLOB exists after the run
# Paths in COMMAND should be absolute: the run directory is a fresh one.
set -uo pipefail

stdout_patterns=()
same_as=""
absent=()
present=()
while [[ $# -gt 0 && $1 != -- ]]; do
  case $1 in
    --stdout) stdout_patterns+=("$2"); shift 2 ;;
    --same-as) same_as=$2; shift 2 ;;
    --absent) absent+=("$2"); shift 2 ;;
    --present) present+=("$2"); shift 2 ;;
    *) echo "$0: unknown check '$1'" >&2; exit 2 ;;
  esac
done
if [[ $# -lt 2 ]]; then
  echo "usage: $0 [CHECK...] -- COMMAND [ARGUMENTS...]" >&2
  exit 2
fi
shift

dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
(cd "$dir" && "$@" >"$dir/.stdout" 2>"$dir/.stderr")
rc=$?
echo "--- standard output (exit code $rc):"
cat "$dir/.stdout"
echo "--- standard error:"
cat "$dir/.stderr"

failed=0
fail() {
  echo "FAIL: $*"
  failed=1
}
[[ $rc -eq 0 ]] || fail "exit code $rc, expected 0"
for p in "${stdout_patterns[@]}"; do
  grep -q -E -e "$p" "$dir/.stdout" || fail "standard output does not match: $p"
done
if [[ -n $same_as ]]; then
  cmp -s "$same_as" "$dir/.stdout" ||
    { fail "standard output differs from $same_as:"; diff "$same_as" "$dir/.stdout" | head -40; }
fi
shopt -s nullglob globstar
for g in "${absent[@]}"; do
  found=("$dir"/$g)
  [[ ${#found[@]} -eq 0 ]] || fail "files that should not exist: ${found[*]#"$dir"/}"
done
for g in "${present[@]}"; do
  found=("$dir"/$g)
  [[ ${#found[@]} -gt 0 ]] || fail "no file matches $g"
done
[[ $failed -eq 0 ]] || exit 1
echo "PASS"
