#!/bin/bash
# globals_append.sh CSV ROWS COMMAND...: runs COMMAND (pd_app) in the
# background and checks that the globals CSV it writes grows by appended
# rows, one file from the first row to the last (tail -f follows it): its
# inode once it has 3 lines equals its inode at the end, and it ends with
# ROWS rows after the header.
set -u
csv=$1 rows=$2
shift 2
rm -rf output
"$@" > run.stdout 2> run.stderr &
pid=$!
for ((i = 0; i < 2000; ++i)); do
  [[ -f $csv && $(wc -l < "$csv") -ge 3 ]] && break
  kill -0 $pid 2> /dev/null || break
  sleep 0.01
done
kill -0 $pid 2> /dev/null || { echo "FAIL: the run ended before its CSV had 3 rows"; exit 1; }
first=$(stat -c %i "$csv")
wait $pid || { tail -n 5 run.stderr; echo "FAIL: the run failed"; exit 1; }
last=$(stat -c %i "$csv")
lines=$(wc -l < "$csv")
echo "inode with $(head -n 3 "$csv" | wc -l) lines: $first, at the end: $last; $lines lines"
[[ $first == "$last" ]] || { echo "FAIL: the CSV was replaced during the run"; exit 1; }
[[ $lines -eq $((rows + 1)) ]] || { echo "FAIL: $lines lines, expected $((rows + 1))"; exit 1; }
echo PASS
