#!/usr/bin/env bash
# with_fifo.sh FIFO COMMAND [ARGUMENTS...]
#
# Makes the named pipe FIFO (if it is not there yet) and runs COMMAND: the
# parameter file tests for a file that is not a regular file. Nothing ever
# writes to the pipe, so a program that opens it for reading blocks forever;
# the test's TIMEOUT catches that.
set -uo pipefail
if [[ $# -lt 2 ]]; then
  echo "usage: $0 FIFO COMMAND [ARGUMENTS...]" >&2
  exit 2
fi
fifo=$1
shift
# The 1- and 2-rank tests may run at once: either may make the pipe.
mkfifo "$fifo" 2>/dev/null || [[ -p $fifo ]] || { echo "cannot make the FIFO $fifo" >&2; exit 2; }
exec "$@"
