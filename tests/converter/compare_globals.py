#!/usr/bin/env python3
"""compare_globals.py [--rtol R] [--atol A] EXPECTED.csv ACTUAL.csv

Two globals CSVs of pd_app: the same columns, the same rows, and every value
of ACTUAL within max(A, R |expected|) of EXPECTED. Prints the largest
relative difference of each column (0 where both are 0), and exits with 1 if
a value is out of tolerance or the files differ in shape."""
import argparse
import csv
import sys

ap = argparse.ArgumentParser()
ap.add_argument("--rtol", type=float, default=1e-9)
ap.add_argument("--atol", type=float, default=0.0)
ap.add_argument("expected")
ap.add_argument("actual")
args = ap.parse_args()


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        sys.exit("FAIL: %s is empty" % path)
    return rows[0], [[float(v) for v in row] for row in rows[1:]]


head_e, rows_e = read(args.expected)
head_a, rows_a = read(args.actual)
if head_e != head_a:
    sys.exit("FAIL: the columns differ:\n  %s\n  %s" % (",".join(head_e), ",".join(head_a)))
if len(rows_e) != len(rows_a):
    sys.exit("FAIL: %d rows expected, %d found" % (len(rows_e), len(rows_a)))
failed = False
print("%-20s %s" % ("column", "max relative difference"))
for j, name in enumerate(head_e):
    worst = 0.0
    for i, (re_, ra) in enumerate(zip(rows_e, rows_a)):
        e, a = re_[j], ra[j]
        d = abs(a - e)
        rel = d / abs(e) if e != 0 else (0.0 if d == 0 else float("inf"))
        worst = max(worst, rel)
        if d > max(args.atol, args.rtol * abs(e)):
            print("  row %d (step %g), %s: expected %r, found %r" % (i + 1, re_[0], name, e, a))
            failed = True
    print("%-20s %.3g" % (name, worst))
if failed:
    print("FAIL: values differ by more than max(%g, %g |expected|)" % (args.atol, args.rtol))
    sys.exit(1)
print("PASS: %d rows, %d columns within max(%g, %g |expected|)" % (len(rows_e), len(head_e), args.atol, args.rtol))
