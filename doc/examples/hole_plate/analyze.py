#!/usr/bin/env python3
"""The plate with the off-centre hole: when and where each run's cracks run,
a table and a picture (README.md).

  python3 analyze.py [RUN_DIR ...]   (default: every output/*/ that holds hole.pvd)

For each run, from the damage at the last field step (the .pvtu's pieces,
read without VTK by ../pvtu_cells.py), seen from above (the largest damage
through the thickness, one pixel per point of the grid): in each column of
points, the runs of points with damage >= 0.3 (gaps of up to two points
closed) are the cracks' strands; the path table gives their centres' y at
x = 5, 20, 50, 70 and 95 mm. From the globals CSV (the Crack tip computes
from the hole's centre, to the right and to the left): when each crack
starts (1 mm past the hole's edge), when it reaches the plate's edge (1 mm
before it), and its mean speed in between; the PD points over time. From
the log: wall time, points, bonds, scene memory, conversions. Writes
hole_plate.png: the damage of every run, a row per spacing, a column per
scene, and the PD points over time.
"""

import csv
import glob
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import pvtu_cells  # noqa: E402  (doc/examples/pvtu_cells.py)

CENTRE = (0.035, 0.005)
RADIUS = 0.005
THRESHOLD = 0.3
COLUMNS = (0.005, 0.02, 0.05, 0.07, 0.095)








def strand_centres(image, h, x):
    """The y of the centres of the damaged runs in the column at x (gaps of
    up to two points closed), the hole's own edge left out."""
    i, ny = int(x / h), round(0.04 / h)
    runs = []
    for j in range(ny):
        y = (j + 0.5) * h - 0.02
        if image.get((i, j), 0.0) >= THRESHOLD and (x - CENTRE[0]) ** 2 + (y - CENTRE[1]) ** 2 > (RADIUS + 2 * h) ** 2:
            if runs and j - runs[-1][1] <= 3:
                runs[-1][1] = j
            else:
                runs.append([j, j])
    return [((a + b + 1) / 2 * h - 0.02) for a, b in runs]


def first_time(t, values, level):
    return next((a for a, b in zip(t, values) if b >= level), float("nan"))


def measure(run):
    rows = list(csv.DictReader(open(os.path.join(run, "hole.globals.csv"))))
    image, h = pvtu_cells.top_view(pvtu_cells.read_points(pvtu_cells.field_steps(run, "hole")[-1]))
    t = [float(r["time"]) * 1e6 for r in rows]
    result = dict(image=image, h=h, t=t, paths={x: strand_centres(image, h, x) for x in COLUMNS})
    for side, edge in (("right", 0.1 - CENTRE[0]), ("left", CENTRE[0])):
        tip = [float(r[side]) for r in rows]
        start = first_time(t, tip, RADIUS + 0.001)
        end = first_time(t, tip, edge - 0.001)
        result[side] = (start, end, (edge - 0.002 - RADIUS) / (end - start) * 1e6 if end == end else float("nan"))
    result["pd_points"] = [float(r["pd_points"]) for r in rows] if "pd_points" in rows[0] else None
    log = open(os.path.join(run, "log")).read() if os.path.exists(os.path.join(run, "log")) else ""
    conversions = re.findall(r"adaptivity: +(\d+) conversions", log)
    result.update(wall=pvtu_cells.log_value(log, "wall time").split(" (")[0],
                  bonds=pvtu_cells.log_value(log, "bonds").split(" ")[0],
                  npoints=pvtu_cells.log_value(log, "points").split(" ")[0],
                  memory=pvtu_cells.log_value(log, "scene memory").split(" over")[0],
                  conversions=conversions[0] if conversions else "-")
    return result




def picture(results, out):
    try:
        import matplotlib
    except ImportError:
        print("(no picture: this Python has no matplotlib; Debian: apt install python3-matplotlib, "
              "then /usr/bin/python3 analyze.py)")
        return
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    spacings = sorted({n.rsplit("-", 1)[-1] for n in results}, key=lambda s: -float(s.rstrip("m")))
    scenes = sorted({n.rsplit("-", 1)[0] for n in results})
    fig, axes = plt.subplots(len(spacings), len(scenes) + 1, figsize=(5.2 * len(scenes) + 4, 2.6 * len(spacings)),
                             squeeze=False)
    for ax in axes.flat:
        ax.set_visible(False)
    for name, r in results.items():
        scene, spacing = name.rsplit("-", 1)
        row = spacings.index(spacing)
        ax = axes[row, scenes.index(scene)]
        ax.set_visible(True)
        pvtu_cells.draw_top_view(ax, r["image"], r["h"])
        ax.add_patch(matplotlib.patches.Circle((CENTRE[0] * 1e3, CENTRE[1] * 1e3), RADIUS * 1e3, fill=False, lw=0.8))
        ax.set_xlim(0, 100)
        ax.set_ylim(-20, 20)
        ax.set_title("%s: %s" % (name, r["wall"]), fontsize=9)
        ax.set_ylabel("y (mm)")
        ax.set_xlabel("x (mm)")
        curve = axes[row, len(scenes)]
        curve.set_visible(True)
        points = r["pd_points"] or [float(r["npoints"])] * len(r["t"])
        curve.plot(r["t"], [p / 1e3 for p in points], label=scene)
        curve.set_xlabel("t (µs)")
        curve.set_ylabel("PD points (thousands)")
        curve.set_title("PD points, %s" % spacing, fontsize=9)
        curve.legend(fontsize=8)
    fig.suptitle("Damage at 50 µs seen from above (white: finite elements or the hole)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=100)


runs = sys.argv[1:] or sorted(os.path.dirname(p) for p in glob.glob(os.path.join(HERE, "output", "*", "hole.pvd")))
results = {}
print("| run | points (end) | bonds | scene memory | conversions | right crack: starts, reaches the edge (µs), "
      "mean speed (m/s) | left crack: the same | wall time |")
print("|---|---|---|---|---|---|---|---|")
for run in runs:
    name = os.path.basename(os.path.normpath(run))
    r = measure(run)
    results[name] = r
    print("| %s | %s | %s | %s | %s | %.1f, %.1f, %.0f | %.1f, %.1f, %.0f | %s |" % (
        name, r["npoints"], r["bonds"], r["memory"], r["conversions"], *r["right"], *r["left"], r["wall"]))
print()
print("Crack paths: y (mm) of the damaged strands' centres at x =")
print("| run | " + " | ".join("%g mm" % (x * 1e3) for x in COLUMNS) + " |")
print("|---|" + "---|" * len(COLUMNS))
for name, r in results.items():
    print("| %s | " % name + " | ".join(", ".join("%+.1f" % (y * 1e3) for y in r["paths"][x]) or "-" for x in COLUMNS) + " |")
picture(results, os.path.join(HERE, "hole_plate.png"))
