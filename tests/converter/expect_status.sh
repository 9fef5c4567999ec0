#!/usr/bin/env bash
# expect_status.sh CODE COMMAND [ARGUMENTS...]: runs COMMAND with its
# standard output and error passed through and exits with CODE if COMMAND
# exited with CODE. Otherwise it says so on standard output and exits with 0,
# which the runner's error mode (tests/tools/run.sh error, under
# perideal_error_test) fails as "exit code 0, expected an error": the runner
# alone accepts any non-zero exit code, the converter's tests want exactly 1.
code=$1
shift
"$@"
rc=$?
if [[ $rc -ne $code ]]; then
  echo "expect_status.sh: exit code $rc, expected $code"
  exit 0
fi
exit "$code"
