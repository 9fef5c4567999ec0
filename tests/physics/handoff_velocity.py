#!/usr/bin/env python3
"""handoff_velocity.py CSV QS_STEP STAGE_STEP TOL: in the globals CSV of a
quasistatic solver followed by a stage, the stage's first row's probe_vx
against (probe_ux(QS_STEP) - probe_ux(QS_STEP - 1)) / (t(QS_STEP) -
t(QS_STEP - 1)), the last load step's difference quotient: relative
difference <= TOL. Prints the numbers and PASS or FAIL; exit 1 on FAIL."""
import csv
import sys

path, qs_step, stage_step, tol = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
with open(path) as f:
    rows = {int(float(r["step"])): r for r in csv.DictReader(f)}
u1, u2 = float(rows[qs_step - 1]["probe_ux"]), float(rows[qs_step]["probe_ux"])
t1, t2 = float(rows[qs_step - 1]["time"]), float(rows[qs_step]["time"])
expected = (u2 - u1) / (t2 - t1)
v = float(rows[stage_step]["probe_vx"])
error = abs(v - expected) / abs(expected)
print("probe_vx at step %d = %.12g, (u_%d - u_%d) / (t_%d - t_%d) = %.12g" % (stage_step, v, qs_step, qs_step - 1,
                                                                                qs_step, qs_step - 1, expected))
print("  relative difference %.3g  (<= %g)  %s" % (error, tol, "PASS" if error <= tol else "FAIL"))
sys.exit(0 if error <= tol else 1)
