#!/usr/bin/env python3
"""Crack branching: where and when each run's crack branches, how fast it
runs, a table and a picture (README.md).

  python3 analyze.py [RUN_DIR ...]   (default: every output/*/ that holds branching.pvd)

For each run, from the damage at the last field step (the .pvtu's pieces,
read without VTK by ../pvtu_cells.py), seen from above (the largest damage
through the thickness, one pixel per point of the grid): in each column of points ahead
of the notch, the runs of points with damage >= 0.3 (gaps of up to two
points closed) are the crack's strands. The crack has branched at the
first x from which every column to the end of the damage has two strands or
more; the branches' y at x = 90 mm are the strands' centres there. From the
globals CSV (the Crack tip compute, along x): when the crack starts (tip 1
mm past the notch), when it reaches the branch point, and its speed: the
mean of the compute's rate (over 2 us of rows) from 5 mm past the notch to
the branch point, and the largest; when the crack reaches the far edge (49
mm past the notch); and from the 'upper' and 'lower' computes, how far the
branches reach from the notch's line. From the log: wall time, points,
bonds, scene memory. Writes branching.png: the damage of every run, a row
per spacing, a column per scene (adaptive, all-PD, coupled).
"""

import csv
import glob
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import pvtu_cells  # noqa: E402  (doc/examples/pvtu_cells.py)

NOTCH_TIP = 0.05
THRESHOLD = 0.3
# Rayleigh wave speed of the PMB glass (E = 72 GPa, nu = 1/4, rho = 2440):
# 0.9194 times the shear wave speed sqrt(E / (2 (1 + nu) rho)).
C_R = 0.9194 * math.sqrt(72e9 / (2 * 1.25 * 2440))








def strands(column, ny):
    """The runs of damaged points in one column (a dict j -> damage), gaps of
    up to two points closed: a list of (first j, last j)."""
    runs = []
    for j in range(ny):
        if column.get(j, 0.0) >= THRESHOLD:
            if runs and j - runs[-1][1] <= 3:
                runs[-1][1] = j
            else:
                runs.append([j, j])
    return runs


def branching(image, h):
    nx, ny = round(0.1 / h), round(0.04 / h)
    columns = [{} for _ in range(nx)]
    for (i, j), d in image.items():
        if 0 <= i < nx:
            columns[i][j] = d
    first = int(NOTCH_TIP / h)
    counts = [len(strands(columns[i], ny)) for i in range(nx)]
    last = max((i for i in range(first, nx) if counts[i] > 0), default=first)
    branch = None
    for i in range(first, last + 1):
        if all(c >= 2 for c in counts[i:last + 1]):
            branch = i
            break
    x_branch = (branch + 0.5) * h if branch is not None else float("nan")
    i90 = int(0.09 / h)
    centres = [((a + b + 1) / 2 * h - 0.02) for a, b in strands(columns[i90], ny)]
    return x_branch, centres


def measure(run):
    rows = list(csv.DictReader(open(os.path.join(run, "branching.globals.csv"))))
    image, h = pvtu_cells.top_view(pvtu_cells.read_points(pvtu_cells.field_steps(run, "branching")[-1]))
    x_branch, centres = branching(image, h)
    t = [float(r["time"]) * 1e6 for r in rows]
    tip = [float(r["tip"]) for r in rows]
    rate = [float(r["tip_rate"]) for r in rows]
    start = next((a for a, b in zip(t, tip) if b >= 0.001), float("nan"))
    at_branch = next((a for a, b in zip(t, tip) if b >= x_branch - NOTCH_TIP), float("nan"))
    running = [r for r, b in zip(rate, tip) if 0.005 <= b <= x_branch - NOTCH_TIP]
    speed = sum(running) / len(running) if running else float("nan")
    peak = max((r for r, b in zip(rate, tip) if b >= 0.002), default=float("nan"))
    upper = max(centres) if centres else float("nan")
    lower = min(centres) if centres else float("nan")
    edge = next((a for a, b in zip(t, tip) if b >= 0.049), float("nan"))
    reach = (float(rows[-1]["upper"]), float(rows[-1]["lower"]))
    log = open(os.path.join(run, "log")).read() if os.path.exists(os.path.join(run, "log")) else ""
    return dict(image=image, h=h, x_branch=x_branch, branches=len(centres), upper=upper, lower=lower,
                start=start, at_branch=at_branch, speed=speed, peak=peak, edge=edge, reach=reach,
                wall=pvtu_cells.log_value(log, "wall time").split(" (")[0],
                bonds=pvtu_cells.log_value(log, "bonds").split(" ")[0],
                npoints=pvtu_cells.log_value(log, "points").split(" ")[0],
                memory=pvtu_cells.log_value(log, "scene memory").split(" over")[0])




def picture(results, out):
    try:
        import matplotlib
    except ImportError:
        print("(no picture: this Python has no matplotlib; Debian: apt install python3-matplotlib, "
              "then /usr/bin/python3 analyze.py)")
        return
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    # One row per spacing (coarsest first), one column per scene (by name).
    spacings = sorted({n.rsplit("-", 1)[-1] for n in results}, key=lambda s: -float(s.rstrip("m")))
    scenes = sorted({n.rsplit("-", 1)[0] for n in results})
    fig, axes = plt.subplots(len(spacings), len(scenes), figsize=(5.2 * len(scenes), 2.5 * len(spacings)),
                             squeeze=False)
    for ax in axes.flat:
        ax.set_visible(False)
    for name, r in results.items():
        scene, spacing = name.rsplit("-", 1)
        ax = axes[spacings.index(spacing), scenes.index(scene)]
        ax.set_visible(True)
        pvtu_cells.draw_top_view(ax, r["image"], r["h"])
        ax.plot([0, 50], [0, 0], "k-", lw=1.5)
        if r["x_branch"] == r["x_branch"]:
            ax.axvline(r["x_branch"] * 1e3, color="w", ls="--", lw=0.8)
        ax.set_xlim(0, 100)
        ax.set_ylim(-20, 20)
        ax.set_title("%s: branches at x = %.1f mm, %.1f µs" % (name, r["x_branch"] * 1e3, r["at_branch"]), fontsize=9)
        ax.set_ylabel("y (mm)")
        ax.set_xlabel("x (mm)")
    fig.suptitle("Damage at 46 µs seen from above (white: finite elements; dashed: the branch point)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=100)


runs = sys.argv[1:] or sorted(os.path.dirname(p) for p in glob.glob(os.path.join(HERE, "output", "*", "branching.pvd")))
results = {}
print("Rayleigh wave speed c_R = %.0f m/s" % C_R)
print("| run | points | bonds | scene memory | crack starts (µs) | branches at x (mm) | at (µs) "
      "| speed before (m/s) | /c_R | peak speed (m/s) | branches' y at 90 mm (mm) | at the far edge (mm) "
      "| far edge at (µs) | wall time |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
for run in runs:
    name = os.path.basename(os.path.normpath(run))
    r = measure(run)
    results[name] = r
    print("| %s | %s | %s | %s | %.1f | %.1f | %.1f | %.0f | %.2f | %.0f | %+.1f / %+.1f | %+.1f / %+.1f | %.1f | %s |" % (
        name, r["npoints"], r["bonds"], r["memory"], r["start"], r["x_branch"] * 1e3, r["at_branch"], r["speed"],
        r["speed"] / C_R, r["peak"], r["upper"] * 1e3, r["lower"] * 1e3, r["reach"][0] * 1e3, -r["reach"][1] * 1e3,
        r["edge"], r["wall"]))
picture(results, os.path.join(HERE, "branching.png"))
