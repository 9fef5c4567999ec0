"""Plots of the plastic dog-bone run (params.prm): the force-elongation curve
and the equivalent plastic strain at the end.

  python3 plot.py [OUTPUT_DIR]      (default: output; needs numpy, matplotlib:
                                     Debian's python3-matplotlib)

Writes force_elongation.png and plastic_strain.png next to this script and
prints the numbers of the README: the elastic slope of the force over the
gauge elongation (fitted below half the yield force), and the plateau (mean
force over the last quarter of the run) against F_y = Y A.
"""
import base64
import csv
import glob
import os
import re
import struct
import sys
import zlib

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

Y = 300e6                   # yield stress (params.prm)
A = 6.35e-3 * 3.15e-3       # reduced section
FY = Y * A
E_CLASSICAL = 180.00e9      # 9KG/(3K+G)
E_N4 = 209.51e9             # ../dogbone_tensile, omega = 1, n = 4 (LPS elastic)

here = os.path.dirname(os.path.abspath(__file__))
out = sys.argv[1] if len(sys.argv) > 1 else "output"


def read_globals(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


def data_arrays(path):
    """Name -> numpy array of every DataArray of a deal.II .vtu piece
    (ascii, or binary base64 with or without zlib compression)."""
    text = open(path).read()
    head = re.search(r"<VTKFile[^>]*>", text).group(0)
    htype = "Q" if 'header_type="UInt64"' in head else "I"
    hsize = struct.calcsize(htype)
    compressed = "vtkZLibDataCompressor" in head
    kinds = {"Float32": "f", "Float64": "d", "Int32": "i", "UInt32": "I", "Int64": "q", "UInt64": "Q", "UInt8": "B"}
    result = {}
    for m in re.finditer(r"<DataArray([^>]*)>\s*([^<]*)<", text):
        attrs, raw = m.group(1), m.group(2).strip()
        name = re.search(r'Name="([^"]*)"', attrs)
        name = name.group(1) if name else "Points"
        fmt = kinds[re.search(r'type="([^"]*)"', attrs).group(1)]
        if 'format="ascii"' in attrs:
            result[name] = np.array(raw.split(), dtype=float)
            continue
        if compressed:
            first = base64.b64decode(raw[:4 * ((3 * hsize + 2) // 3)])
            nb = struct.unpack("<" + htype, first[:hsize])[0]
            hlen = 4 * (((3 + nb) * hsize + 2) // 3)
            h = base64.b64decode(raw[:hlen])
            sizes = struct.unpack("<%d%s" % (nb, htype), h[3 * hsize:(3 + nb) * hsize])
            data = base64.b64decode(raw[hlen:])
            blob, pos = b"", 0
            for s in sizes:
                blob += zlib.decompress(data[pos:pos + s])
                pos += s
        else:
            blob = base64.b64decode(raw)[hsize:]
        result[name] = np.frombuffer(blob, dtype="<" + fmt).astype(float)
    return result


def last_step_cells(directory, field):
    """Top faces (x, y) of the cells in the top layer, and the cells' field
    value, of the last output step."""
    stems = sorted(set(re.sub(r"\.\d+\.vtu$", "", f) for f in glob.glob(directory + "/dogbone_*.vtu")))
    faces, values, zs = [], [], []
    for piece in glob.glob(stems[-1] + ".*.vtu"):
        arrays = data_arrays(piece)
        points = arrays["Points"].reshape(-1, 3)
        conn = arrays["connectivity"].astype(int).reshape(-1, 8)
        value = arrays[field]
        for cell in conn:
            # the top face: the 4 vertices of largest z, in order around it
            v = points[cell]
            top = v[np.argsort(v[:, 2])[4:], :2]
            c = top.mean(axis=0)
            faces.append(top[np.argsort(np.arctan2(top[:, 1] - c[1], top[:, 0] - c[0]))])
            zs.append(v[:, 2].mean())
            values.append(value[cell[0]])
    faces, values, zs = np.array(faces), np.array(values), np.array(zs)
    top = zs > zs.max() - 1e-6
    return faces[top], values[top]


g = read_globals(os.path.join(out, "dogbone.globals.csv"))
gauge = g["x_right"] - g["x_left"]
elong = g["u_right"] - g["u_left"]          # gauge elongation
force = -g["f_grip"]                        # the right grip's pull
grip = 2 * g["u_grip"]                      # grip separation

elastic = force < 0.5 * FY
slope = np.polyfit(elong[elastic], force[elastic], 1)[0]
E_fit = slope * gauge[0] / A
late = g["time"] >= 0.75 * g["time"][-1]
plateau = force[late].mean()
print("gauge length %.5g mm" % (1e3 * gauge[0]))
print("elastic slope: E = %.4g GPa (LPS elastic at n = 4, omega = 1: %.2f GPa; classical %.2f GPa)"
      % (E_fit / 1e9, E_N4 / 1e9, E_CLASSICAL / 1e9))
print("plateau (last quarter, mean): %.1f N, F_y = Y A = %.1f N, ratio %.4f; range %.1f .. %.1f N"
      % (plateau, FY, plateau / FY, force[late].min(), force[late].max()))
print("largest force %.1f N (%.4f F_y); final gauge strain %.4g, grip separation %.4g mm"
      % (force.max(), force.max() / FY, elong[-1] / gauge[0], 1e3 * grip[-1]))

fig, ax = plt.subplots(figsize=(7, 4.5))
ax.plot(1e3 * elong, force / 1e3, "k.-", lw=1, ms=3, label="PeriDeal, Elastic plastic (n = 4)")
e = np.linspace(0, 1e3 * elong.max(), 50)
ax.plot(e, E_N4 * A / gauge[0] * e / 1e6, "b--", lw=1,
        label="elastic slope of the LPS example at n = 4 (E = 209.5 GPa)")
ax.plot(e, E_CLASSICAL * A / gauge[0] * e / 1e6, "c:", lw=1, label="classical E = 9KG/(3K+G) = 180 GPa")
ax.axhline(FY / 1e3, color="r", ls="--", lw=1, label="F_y = Y A = %.0f N" % FY)
ax.set_ylim(0, 1.25 * FY / 1e3)
ax.set_xlabel("gauge elongation [mm] (gauge %.2f mm)" % (1e3 * gauge[0]))
ax.set_ylabel("grip force [kN]")
ax.set_title("Dog-bone tensile test through yield (Y = 300 MPa, perfectly plastic)")
ax.legend(loc="lower right", fontsize=8)
ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(os.path.join(here, "force_elongation.png"), dpi=120)

faces, eps = last_step_cells(out, "Equivalent plastic strain")
fig, ax = plt.subplots(figsize=(10, 2.6))
pc = PolyCollection(1e3 * faces, array=eps, cmap="viridis", edgecolors="none")
ax.add_collection(pc)
ax.set_xlim(-52, 52)
ax.set_ylim(-7, 7)
ax.set_aspect("equal")
ax.set_xlabel("x [mm]")
ax.set_ylabel("y [mm]")
ax.set_title("Equivalent plastic strain at t = %.0f us (top face, reference configuration)" % (1e6 * g["time"][-1]))
fig.colorbar(pc, ax=ax, fraction=0.03, pad=0.01)
fig.tight_layout()
fig.savefig(os.path.join(here, "plastic_strain.png"), dpi=120)
print("plastic strain: max %.4g, cells of the top face yielded: %d of %d" % (eps.max(), (eps > 0).sum(), len(eps)))
