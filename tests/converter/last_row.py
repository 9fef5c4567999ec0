#!/usr/bin/env python3
"""last_row.py CSV COLUMN EXPECTED TOLERANCE: exit status 0 if the last row of
the globals CSV has |COLUMN - EXPECTED| <= TOLERANCE, else 1 with a line
naming the value (a CHECK of tests/converter/CMakeLists.txt)."""
import csv
import sys

path, column, expected, tolerance = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
with open(path, newline="") as f:
    rows = list(csv.DictReader(f))
if not rows or column not in rows[-1]:
    sys.exit("%s: no column '%s' in a last row" % (path, column))
value = float(rows[-1][column])
if abs(value - expected) > tolerance:
    sys.exit("%s: last %s = %r, expected %r within %g" % (path, column, value, expected, tolerance))
print("last %s = %r (expected %r within %g)" % (column, value, expected, tolerance))
