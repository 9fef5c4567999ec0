#!/usr/bin/env python3
"""Checks the output field 'Number of neighbors' of a run: at every point it
must equal the size of the point's family, the other points within the
horizon of the point's own block (distance <= horizon (1 + 1e-9)), counted
here from the cell centres of the field file.

    neighbor_count.py RUN.pvtu HORIZON_OF_BLOCK_0 [HORIZON_OF_BLOCK_1 ...]

Exit status 1 if any point differs."""

import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from compare_vtu import Checks, cells  # noqa: E402


def main():
    pvtu, horizons = sys.argv[1], [float(h) for h in sys.argv[2:]]
    found, _ = cells(pvtu)
    points = []
    for xyz, values in found:
        centre = [sum(v[d] for v in xyz) / 8 for d in range(3)]
        points.append((centre, int(round(values["Block"][0][0])), values["Number of neighbors"][0][0]))
    wrong, larger = 0, 0
    for i, (x, block, written) in enumerate(points):
        reach = horizons[block] * (1 + 1e-9)
        family = sum(1 for j, (y, _, _) in enumerate(points) if j != i and math.dist(x, y) <= reach)
        wrong += written != family
        larger = max(larger, written - family)
    print("points: %d, blocks' horizons: %s" % (len(points), ", ".join(map(str, horizons))))
    checks = Checks()
    checks("Number of neighbors = family size at every point (%d differ, by up to %g)" % (wrong, larger),
           wrong == 0)
    return checks.finish()


if __name__ == "__main__":
    sys.exit(main())
