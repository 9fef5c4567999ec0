#!/usr/bin/env python3
"""Kalthoff-Winkler: the crack angle of each run, a table and a picture (README.md).

  python3 analyze.py [RUN_DIR ...]    (default: every output/*/ that holds kw.pvd)
  python3 analyze.py --sequence RUN_DIR   kw_sequence.png: every field step of one run

For each run: the damage at the last field step (the .pvtu's pieces, read
without VTK by ../pvtu_cells.py), the points with damage >= 0.3 in the upper crack's path
(x > 50 mm, y > 25 mm) between 12 and 35 mm from its notch tip (50, 25) mm,
and the direction through the tip that fits them best (total least squares:
the principal axis of their offsets from the tip). The angle is measured
from the notch (+x) towards +y, as the experiment's 70 degrees. The lower
crack mirrors it (the scene is symmetric about y = 0; the table shows both).
From the globals CSV, the Crack tip computes: when the upper crack has run
5 mm along y, and its speed along the path while it runs 10 to 40 mm along
y (the rate of 'upper_tip_y' over sin(angle)). From the log: wall time,
points, bonds. Writes kw_damage.png, the damage of the runs named in
PICTURE (top view, the largest damage through the thickness).
"""

import csv
import glob
import math
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import pvtu_cells  # noqa: E402  (doc/examples/pvtu_cells.py)

TIP = (0.05, 0.025)
R_MIN, R_MAX = 0.012, 0.035
PICTURE = ["pmb-1mm", "lps-1mm", "energy-1mm"]


def read_points(pvtu):
    """(x, y, z, damage) of every PD point."""
    return [c[:4] for c in pvtu_cells.read_cells(pvtu, "Damage")]


def last_pvtu(run):
    steps = sorted(glob.glob(os.path.join(run, "kw_*.pvtu")), key=lambda f: int(re.findall(r"_(\d+)\.pvtu", f)[0]))
    return steps[-1]


def crack_angle(points, sign):
    """Angle in degrees of the crack from the notch tip at (50, sign 25) mm."""
    sxx = sxy = syy = 0.0
    n = 0
    for x, y, z, d in points:
        dx, dy = x - TIP[0], sign * y - TIP[1]
        r = math.hypot(dx, dy)
        if d >= 0.3 and dx > 0 and dy > 0 and R_MIN <= r <= R_MAX:
            sxx += dx * dx
            sxy += dx * dy
            syy += dy * dy
            n += 1
    if n < 3:
        return float("nan"), n
    # The principal axis of [[sxx, sxy], [sxy, syy]].
    angle = 0.5 * math.atan2(2 * sxy, sxx - syy)
    return math.degrees(angle), n


def measure(run):
    rows = list(csv.DictReader(open(os.path.join(run, "kw.globals.csv"))))
    points = read_points(last_pvtu(run))
    upper, n_upper = crack_angle(points, 1)
    lower, n_lower = crack_angle(points, -1)
    start = next((float(r["time"]) * 1e6 for r in rows if float(r["upper_tip_y"]) >= 0.005), float("nan"))
    s = math.sin(math.radians(upper)) if upper == upper else float("nan")
    running = [float(r["upper_tip_y_rate"]) / s for r in rows if 0.010 <= float(r["upper_tip_y"]) <= 0.040]
    speed = sum(running) / len(running) / 1000 if running else float("nan")
    log = open(os.path.join(run, "log")).read() if os.path.exists(os.path.join(run, "log")) else ""
    return dict(upper=upper, lower=lower, n=n_upper, start=start, speed=speed, points=points,
                wall=pvtu_cells.log_value(log, "wall time").split(" (")[0],
                bonds=pvtu_cells.log_value(log, "bonds").split(" ")[0],
                npoints=pvtu_cells.log_value(log, "points").split(" ")[0])


def draw_top_view(ax, points):
    """The damage seen from above: the largest through the thickness, one
    pixel per point of the plate's grid (spacing from the points' x)."""
    xs = sorted({round(p[0] * 1e6) for p in points})
    h = (xs[-1] - xs[0]) / (len(xs) - 1) * 1e-6
    nx, ny = round(0.1 / h), round(0.2 / h)
    image = [[0.0] * nx for _ in range(ny)]
    for x, y, z, d in points:
        i, j = min(nx - 1, int(x / h)), min(ny - 1, int((y + 0.1) / h))
        image[j][i] = max(image[j][i], d)
    ax.imshow(image, origin="lower", extent=(0, 100, -100, 100), cmap="jet", vmin=0, vmax=1, interpolation="nearest")


def picture(results, out):
    try:
        import matplotlib
    except ImportError:
        print("(no picture: this Python has no matplotlib; Debian: apt install python3-matplotlib, "
              "then /usr/bin/python3 analyze.py)")
        return
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    names = [n for n in PICTURE if n in results]
    if not names:
        return
    fig, axes = plt.subplots(1, len(names), figsize=(3.4 * len(names), 5.9), squeeze=False)
    for ax, name in zip(axes[0], names):
        draw_top_view(ax, results[name]["points"])
        for sign in (1, -1):
            ax.plot([0, 50], [sign * 25, sign * 25], "k-", lw=1.5)
            a = math.radians(70)
            ax.plot([50, 50 + 75 / math.tan(a)], [sign * 25, sign * 100], "w--", lw=1)
        ax.set_xlim(0, 100)
        ax.set_ylim(-100, 100)
        ax.set_title("%s: %.1f°" % (name, results[name]["upper"]), fontsize=10)
        ax.set_xlabel("x (mm)")
    axes[0][0].set_ylabel("y (mm)")
    fig.suptitle("Kalthoff–Winkler, damage at 90 µs (dashed: 70°, the experiment)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)


def sequence(run, out):
    """The damage of every field step of one run, side by side (a run with
    Output/Frequency = 100, e.g.)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    steps = sorted(glob.glob(os.path.join(run, "kw_*.pvtu")), key=lambda f: int(re.findall(r"_(\d+)\.pvtu", f)[0]))[1:]
    times = {}
    for line in open(os.path.join(run, "kw.pvd")):
        m = re.search(r'timestep="([^"]+)".*file="([^"]+)"', line)
        if m:
            times[os.path.basename(m.group(2))] = float(m.group(1))
    # The last step right after a regular one adds nothing: drop the regular one.
    t = [times.get(os.path.basename(f), 0.0) for f in steps]
    steps = [f for k, f in enumerate(steps) if k + 1 == len(steps) or t[k + 1] - t[k] > 0.1 * (t[1] - t[0])]
    fig, axes = plt.subplots(1, len(steps), figsize=(2.4 * len(steps), 4.6), squeeze=False)
    for ax, f in zip(axes[0], steps):
        draw_top_view(ax, read_points(f))
        ax.set_title("%.0f µs" % (times.get(os.path.basename(f), float("nan")) * 1e6), fontsize=10)
        ax.set_xticks([0, 50, 100])
    fig.tight_layout()
    fig.savefig(out, dpi=90)


if len(sys.argv) == 3 and sys.argv[1] == "--sequence":
    sequence(sys.argv[2], os.path.join(HERE, "kw_sequence.png"))
    sys.exit(0)
runs = sys.argv[1:] or sorted(os.path.dirname(p) for p in glob.glob(os.path.join(HERE, "output", "*", "kw.pvd")))
results = {}
print("| run | points | bonds | angle upper (°) | angle lower (°) | points fitted | crack runs 5 mm at (µs) "
      "| crack speed (km/s) | wall time |")
print("|---|---|---|---|---|---|---|---|---|")
for run in runs:
    name = os.path.basename(os.path.normpath(run))
    r = measure(run)
    results[name] = r
    print("| %s | %s | %s | %.1f | %.1f | %d | %.1f | %.2f | %s |" % (name, r["npoints"], r["bonds"], r["upper"],
                                                                 r["lower"], r["n"], r["start"], r["speed"], r["wall"]))
picture(results, os.path.join(HERE, "kw_damage.png"))
