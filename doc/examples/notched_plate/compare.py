#!/usr/bin/env python3
"""Compare the coupled and the all-PD notched plate (README.md).

  python3 compare.py [DIR]     (DIR holds output/coupled.* and output/all_pd.*
                                and the logs coupled.log, all_pd.log; default .)

From the globals CSVs: the time the crack reaches each probe (its largest
damage first at or above 0.3: the points on either side of the crack line
lose a third to a half of their bonds as it passes), the crack speed (least-squares slope of probe
position against arrival time), the peak of the top grip's reaction
(-force_top), the Crack tip compute's speed (the mean of tip_rate while the
tip is 5 to 40 mm past the notch) and the broken bonds at the end; from the logs (pd_app's
closing summary): wall time, bonds and scene memory. Prints a markdown table
with the coupled run's relative difference and checks it against the stated
tolerances: arrival times and both crack speeds within 5%, peak reaction within
5%, broken bonds within 5%, and a speed-up of at least 3. Exit code 1 if
one fails.
"""

import csv
import os
import re
import sys

DIR = sys.argv[1] if len(sys.argv) > 1 else "."
PROBES = [55, 60, 70, 80, 90]  # mm


def read(run):
    rows = list(csv.DictReader(open(os.path.join(DIR, "output", run + ".globals.csv"))))
    arrival = {}
    for r in rows:
        for x in PROBES:
            if x not in arrival and float(r["damage%d" % x]) >= 0.3:
                arrival[x] = float(r["time"]) * 1e6
    peak = max(rows, key=lambda r: -float(r["force_top"]))
    xs = [x for x in PROBES if x in arrival]
    speed = float("nan")
    if len(xs) >= 2:
        ts = [arrival[x] for x in xs]
        mt, mx = sum(ts) / len(ts), sum(xs) / len(xs)
        speed = sum((t - mt) * (x - mx) for t, x in zip(ts, xs)) / sum((t - mt) ** 2 for t in ts)  # mm/us = km/s
    # The Crack tip compute's own speed (tip_rate, its least-squares slope
    # over 5 us of rows), averaged over the rows with the tip 5 to 40 mm past
    # the notch: the probes' span.
    running = [float(r["tip_rate"]) for r in rows if 0.005 <= float(r["tip"]) <= 0.040]
    tip_speed = sum(running) / len(running) / 1000 if running else float("nan")  # m/s -> km/s
    log = open(os.path.join(DIR, run + ".log")).read()

    def summary(key):
        m = re.search(r"^  " + key + r":\s+(.*)$", log, re.M)
        return m.group(1) if m else ""

    wall = summary("wall time")
    m = re.match(r"(?:(\d+) min )?([\d.]+) s", wall)
    seconds = (int(m.group(1) or 0) * 60 + float(m.group(2))) if m else float("nan")
    bonds = int(summary("bonds").split()[0])
    memory = summary("scene memory").split(" MiB")[0]
    return dict(arrival=arrival, speed=speed, tip_speed=tip_speed, peak=-float(peak["force_top"]), peak_time=float(peak["time"]) * 1e6,
                broken=float(rows[-1]["broken_bonds"]), seconds=seconds, bonds=bonds, memory=float(memory))


pd, cp = read("all_pd"), read("coupled")
failures = 0


def row(name, a, b, tol=None, fmt="%.1f"):
    global failures
    rel = (b - a) / a if a else float("nan")
    ok = "" if tol is None else ("PASS" if abs(rel) <= tol else "FAIL")
    failures += ok == "FAIL"
    bound = "" if tol is None else "±%g%%" % (100 * tol)
    print("| %s | %s | %s | %+.1f%% | %s %s |" % (name, fmt % a, fmt % b, 100 * rel, bound, ok))


print("| | all-PD | coupled | difference | tolerance |")
print("|---|---|---|---|---|")
for x in PROBES:
    if x in pd["arrival"] and x in cp["arrival"]:
        row("crack at x = %d mm (µs)" % x, pd["arrival"][x], cp["arrival"][x], 0.05)
    else:
        print("| crack at x = %d mm | %s | %s | not reached | FAIL |" % (x, pd["arrival"].get(x), cp["arrival"].get(x)))
        failures += 1
row("crack speed 55–90 mm (km/s)", pd["speed"], cp["speed"], 0.05, "%.2f")
row("crack speed, Crack tip compute (km/s)", pd["tip_speed"], cp["tip_speed"], 0.05, "%.2f")
row("peak reaction of a grip (N)", pd["peak"], cp["peak"], 0.05)
row("time of the peak (µs)", pd["peak_time"], cp["peak_time"])
row("broken bonds (pairs, globals' broken_bonds) at 100 µs", pd["broken"], cp["broken"], 0.05, "%.0f")
row("bonds (directed)", pd["bonds"], cp["bonds"], None, "%.0f")
row("scene memory (MiB)", pd["memory"], cp["memory"], None, "%.1f")
row("wall time on 2 ranks (s)", pd["seconds"], cp["seconds"], None, "%.1f")
speedup = pd["seconds"] / cp["seconds"]
ok = speedup >= 3
failures += not ok
print("\nspeed-up (all-PD wall time / coupled): %.2f (at least 3: %s)" % (speedup, "PASS" if ok else "FAIL"))
print("memory ratio (coupled / all-PD): %.2f" % (cp["memory"] / pd["memory"]))
sys.exit(1 if failures else 0)
