#!/usr/bin/env python3
"""Compares the field files of two runs of one scene, one written with
Output/Field precision = float (deal.II's writer) and one with double
(PeriDeal's own), on any numbers of ranks: the same cells (matched by their
centres), each cell's 8 vertices in the same (VTK) order, the same arrays
with the same components, and every value equal to the float file's within
its Float32 rounding (relative RTOL of the array's largest magnitude).
Checks that the double files' data arrays are Float64.

    compare_vtu.py FLOAT.pvtu DOUBLE.pvtu [--rtol 1e-6]

Reads VTU pieces as deal.II 9.4 writes them (base64, one zlib block per
array after a 4-word UInt32 header). Prints each array's largest relative
difference and PASS/FAIL; exit status 1 on a failure."""

import argparse
import base64
import os
import re
import struct
import sys
import zlib

TYPES = {"Float32": "f", "Float64": "d", "Int32": "i", "UInt8": "B"}


def arrays(vtu):
    """{name: (type, components, values)} of a piece; the points as 'Points'."""
    text = open(vtu).read()
    if "vtkZLibDataCompressor" not in text:
        raise SystemExit(vtu + ": not zlib-compressed as deal.II writes it")
    found = {}
    for match in re.finditer(r"<DataArray([^>]*)>\s*([^<]*)</DataArray>", text):
        attributes, body = match.group(1), match.group(2).strip()
        kind = re.search(r'type="(\w+)"', attributes).group(1)
        name = re.search(r'Name="([^"]*)"', attributes)
        name = name.group(1) if name else "Points"
        components = re.search(r'NumberOfComponents="(\d+)"', attributes)
        components = int(components.group(1)) if components else 1
        header = struct.unpack("<4I", base64.b64decode(body[:24]))
        if header[0] != 1:
            raise SystemExit(vtu + ": array '" + name + "' has " + str(header[0]) + " zlib blocks")
        raw = zlib.decompress(base64.b64decode(body[24:]))
        code = TYPES[kind]
        values = struct.unpack("<" + str(len(raw) // struct.calcsize(code)) + code, raw)
        found[name] = (kind, components, values)
    return found


def pieces(pvtu):
    folder = os.path.dirname(pvtu)
    return [os.path.join(folder, p) for p in re.findall(r'<Piece Source="([^"]+)"', open(pvtu).read())]


def cells(pvtu):
    """Every cell of every piece: its 8 vertices in VTK order (through the
    connectivity) with the arrays' values there, and the arrays' types."""
    found, types = [], {}
    for piece in pieces(pvtu):
        a = arrays(piece)
        points, connectivity, offsets = a["Points"][2], a["connectivity"][2], a["offsets"][2]
        data = {n: v for n, v in a.items() if n not in ("Points", "connectivity", "offsets", "types")}
        for name, (kind, components, _) in data.items():
            types[name] = (kind, components)
        start = 0
        for end in offsets:
            vertices = connectivity[start:end]
            start = end
            xyz = [points[3 * v:3 * v + 3] for v in vertices]
            values = {n: [c[v * k:v * k + k] for v in vertices] for n, (_, k, c) in data.items()}
            found.append((xyz, values))
    return found, types


class Checks:
    """Prints each check with PASS/FAIL and counts the failures."""

    def __init__(self):
        self.failures = 0

    def __call__(self, what, ok):
        print("  " + what + ": " + ("PASS" if ok else "FAIL"))
        self.failures += not ok

    def differences(self, worst, scale, rtol, what):
        """A check per name: worst[name] / scale[name] <= rtol; WHAT
        names the difference ('|double - float| / max |float|')."""
        for name in sorted(worst):
            diff = worst[name] / max(scale[name], 1e-300)
            self("'%s': largest %s = %.3g <= %g" % (name, what, diff, rtol), diff <= rtol)

    def finish(self):
        print("ALL PASSED" if self.failures == 0 else "%d CHECK(S) FAILED" % self.failures)
        return 1 if self.failures else 0


def centre_key(edge):
    """A cell's 8 vertices to its centre, binned at a quarter of EDGE (the
    shortest edge): cells of two files match whatever their rounding."""
    return lambda xyz: tuple(int(round(sum(v[d] for v in xyz) / 8 / (edge / 4))) for d in range(3))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("float_pvtu")
    parser.add_argument("double_pvtu")
    parser.add_argument("--rtol", type=float, default=1e-6)
    args = parser.parse_args()
    check = Checks()

    single, single_types = cells(args.float_pvtu)
    double, double_types = cells(args.double_pvtu)
    print("%d cells in the float files, %d in the double files" % (len(single), len(double)))
    check("the same number of cells", len(single) == len(double) and len(single) > 0)
    check("the same arrays with the same components",
          {n: t[1] for n, t in single_types.items()} == {n: t[1] for n, t in double_types.items()})
    check("the double files' arrays are Float64", all(t[0] == "Float64" for t in double_types.values()))
    # Cells matched by their centre (binned at a quarter of the shortest edge:
    # the two files' coordinates differ by Float32 rounding only), whatever
    # the number of ranks (pieces) of each run.
    key = centre_key(min(max(abs(a - b) for a, b in zip(x[0], x[1])) for x, _ in double))
    by_centre = {key(xyz): (xyz, values) for xyz, values in double}
    check("every cell's centre is in both", all(key(xyz) in by_centre for xyz, _ in single))
    scale, worst = {}, {}
    for xyz, values in single:
        other = by_centre.get(key(xyz))
        if other is None:
            continue
        for name, pairs in [("Points", [(xyz, other[0])])] + [(n, [(v, other[1][n])]) for n, v in values.items()]:
            for a, b in pairs:
                for va, vb in zip(a, b):
                    for x, y in zip(va, vb):
                        scale[name] = max(scale.get(name, 0.0), abs(x))
                        worst[name] = max(worst.get(name, 0.0), abs(x - y))
    check.differences(worst, scale, args.rtol, "|double - float| / max |float|")
    return check.finish()


if __name__ == "__main__":
    sys.exit(main())
