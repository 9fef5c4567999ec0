"""Picture and measures of a Taylor bar run (params.prm), without ParaView.

  /usr/bin/python3 plot.py output/taylor_bar.pvd taylor_bar.png

Reads the last step of the .pvd series (deal.II's zlib-compressed binary
.vtu pieces: every cell is one peridynamic point, written with its 8
vertices), moves each point's centroid by its displacement and draws every
point at its deformed radius and height, coloured by the equivalent plastic
strain, over the undeformed outline. Prints the final length (the largest
deformed z of a centroid plus half a cell) and the footprint radius (the
largest deformed radius of a centroid in the first cell layer plus half a
cell), the same measures as the run's globals columns rear_uz and foot_ux.
"""

import base64
import re
import struct
import sys
import zlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def decode(text, dtype):
    """A deal.II binary DataArray: a base64 header of UInt32 block sizes,
    then the base64 of the zlib-compressed blocks."""
    text = text.strip()
    first = base64.b64decode(text[:8])
    blocks = struct.unpack("<I", first[:4])[0]
    header_len = 4 * ((4 * (3 + blocks) + 2) // 3)
    header = struct.unpack("<%dI" % (3 + blocks), base64.b64decode(text[:header_len]))
    data = base64.b64decode(text[header_len:])
    out, pos = b"", 0
    for size in header[3:]:
        out += zlib.decompress(data[pos:pos + size])
        pos += size
    return np.frombuffer(out, dtype=dtype)


def read_piece(path):
    xml = open(path).read()
    arrays = {}
    for m in re.finditer(r'<DataArray type="(\w+)"( Name="([^"]*)")?[^>]*>(.*?)</DataArray>', xml, re.S):
        kind, name, body = m.group(1), m.group(3) or "Points", m.group(4)
        dtype = {"Float32": "<f4", "Float64": "<f8", "Int32": "<i4", "UInt8": "u1"}[kind]
        arrays[name] = decode(body, dtype)
    return arrays


def last_step(pvd):
    import os
    files = re.findall(r'file="([^"]+)"', open(pvd).read())
    pvtu = os.path.join(os.path.dirname(pvd), files[-1])
    pieces = re.findall(r'Source="([^"]+)"', open(pvtu).read())
    return [os.path.join(os.path.dirname(pvd), p) for p in pieces]


X, U, E = [], [], []
for piece in last_step(sys.argv[1]):
    a = read_piece(piece)
    pts = a["Points"].reshape(-1, 8, 3).astype(float)
    X.append(pts.mean(axis=1))
    U.append(a["Displacement"].reshape(-1, 8, 3)[:, 0, :].astype(float))
    E.append(a["Equivalent plastic strain"].reshape(-1, 8)[:, 0].astype(float))
X, U, E = np.vstack(X), np.vstack(U), np.concatenate(E)
h = X[:, 2].min() * 2  # the first layer's centroids lie at h/2
x = X + U
length = x[:, 2].max() + h / 2
first = X[:, 2] < h
foot = np.hypot(x[first, 0], x[first, 1]).max() + h / 2
print("cell size h = %.4g mm, points %d" % (1e3 * h, len(X)))
print("final length     %.3f mm (L0 = 32.4 mm)" % (1e3 * length))
print("footprint radius %.3f mm (r0 = 3.2 mm)" % (1e3 * foot))
print("largest equivalent plastic strain %.3f" % E.max())

r = np.hypot(x[:, 0], x[:, 1])
fig, ax = plt.subplots(figsize=(4.2, 7.0))
ax.plot([0, 3.2, 3.2, 0], [0, 0, 32.4, 32.4], "k--", lw=0.8, label="undeformed")
order = np.argsort(E)
sc = ax.scatter(1e3 * r[order], 1e3 * x[order, 2], c=E[order], s=6, cmap="viridis")
fig.colorbar(sc, ax=ax, label="equivalent plastic strain")
ax.set_aspect("equal")
ax.set_xlabel("radius (mm)")
ax.set_ylabel("z (mm)")
ax.set_title("Taylor bar at 80 us, every point\nL = %.2f mm, footprint r = %.2f mm" % (1e3 * length, 1e3 * foot),
             fontsize=9)
ax.legend(loc="upper right", fontsize=8)
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=130)
