"""The crack's arrival at x = 55, 60, 70, 80 and 90 mm from the globals' Crack
tip column (the first row whose tip, measured from the notch tip at x = 50
mm, reaches 5, 10, 20, 30, 40 mm), the peak grip force and the broken bonds
at the end, for each globals CSV given, side by side with the first.

  python3 tip_times.py output/all_pd.globals.csv output/coupled.globals.csv output/adaptive.globals.csv
"""

import csv
import sys


def summary(path):
    rows = list(csv.DictReader(open(path)))
    arrivals = []
    for distance in (0.005, 0.010, 0.020, 0.030, 0.040):
        hit = next((float(r["time"]) * 1e6 for r in rows if float(r["tip"]) >= distance), None)
        arrivals.append(hit)
    peak = max(abs(float(r["force_top"])) for r in rows)
    return arrivals, peak, float(rows[-1]["broken_bonds"])


if len(sys.argv) < 2:
    raise SystemExit(__doc__)
runs = [(path, summary(path)) for path in sys.argv[1:]]
reference = runs[0][1]
labels = ["crack at x = %d mm (us)" % x for x in (55, 60, 70, 80, 90)] + ["peak grip force (N)", "broken bonds at the end"]
print("| | " + " | ".join(p for p, _ in runs) + " |")
print("|---" * (len(runs) + 1) + "|")
for k, label in enumerate(labels):
    cells = []
    for _, (arrivals, peak, broken) in runs:
        value = (arrivals + [peak, broken])[k]
        ref = (reference[0] + [reference[1], reference[2]])[k]
        text = "never" if value is None else "%.1f" % value if k < 6 else "%.0f" % value
        if value is not None and ref and value is not ref:
            text += " (%+.1f%%)" % (100 * (value / ref - 1))
        cells.append(text)
    print("| " + label + " | " + " | ".join(cells) + " |")
