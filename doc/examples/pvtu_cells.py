"""Reading a run's output without VTK, for the examples' analysis scripts
(kalthoff_winkler/analyze.py, crack_branching/analyze.py, hole_plate/analyze.py).

  read_cells(pvtu, field)  every cell of a .pvtu's pieces: (x, y, z, value, width),
                           its centre (the 8 vertices averaged), the field's
                           value (cell data written per vertex) and its extent
                           along x: each PD point is a cell, and the finest
                           cells are the PD points
  log_value(log, key)      a line '  key: value' of a pd_app log (the summary)
  read_points(pvtu)        (x, y, damage) of every PD point (the finest cells;
                           with a Block field, block 0's only)
  field_steps(run, base)   a run's BASE_*.pvtu files in step order
  top_view(points)         {(i, j): largest damage through the thickness} on
                           the points' grid, and its spacing
  draw_top_view(ax, image, h)  that image on the 100 x 40 mm plate
                           (crack_branching, hole_plate)
"""

import base64
import glob
import os
import re
import struct
import xml.etree.ElementTree as ElementTree
import zlib


def read_array(element):
    """A DataArray as deal.II writes it: ascii, or base64 with a zlib block."""
    text = "".join(element.text.split()) if element.text else ""
    kind = "f" if element.get("type") == "Float32" else "d"
    if not text:
        return []
    if element.get("format") == "ascii":
        return [float(v) for v in text.split()]
    blocks = struct.unpack("<4I", base64.b64decode(text[:24]))[0]
    if blocks != 1:
        raise SystemExit("pvtu_cells.py: %d zlib blocks, expected 1" % blocks)
    raw = zlib.decompress(base64.b64decode(text[24:]))
    n = len(raw) // struct.calcsize(kind)
    return list(struct.unpack("<%d%s" % (n, kind), raw))


def read_cells(pvtu, field):
    record = ElementTree.parse(pvtu).getroot()
    folder = os.path.dirname(pvtu)
    cells = []
    for piece in record.iter("Piece"):
        root = ElementTree.parse(os.path.join(folder, piece.get("Source"))).getroot()
        for p in root.iter("Piece"):
            xyz = read_array(p.find("Points/DataArray"))
            values = None
            for a in p.find("PointData").iter("DataArray"):
                if a.get("Name") == field:
                    values = read_array(a)
            for c in range(len(values) // 8):
                v = xyz[24 * c:24 * c + 24]
                cells.append((sum(v[0::3]) / 8, sum(v[1::3]) / 8, sum(v[2::3]) / 8, values[8 * c],
                              max(v[0::3]) - min(v[0::3])))
    return cells


def log_value(log, key):
    m = re.search(r"^  " + key + r":\s+(.*)$", log, re.M)
    return m.group(1) if m else ""


def read_points(pvtu):
    """(x, y, damage) of every PD point: the finest cells (the finite element
    cells, coarser, are skipped); where the run writes the Block field (the
    adaptive runs, which start with FE cells at the PD spacing), the cells of
    block 0, the peridynamic one, only."""
    cells = read_cells(pvtu, "Damage")
    h = min(c[4] for c in cells)
    try:
        blocks = [c[3] for c in read_cells(pvtu, "Block")]
    except TypeError:  # no Block field
        blocks = [0] * len(cells)
    return [(c[0], c[1], c[3]) for c, b in zip(cells, blocks) if c[4] < 1.5 * h and b == 0]


def field_steps(run, base):
    return sorted(glob.glob(os.path.join(run, base + "_*.pvtu")),
                  key=lambda f: int(re.findall(r"_(\d+)\.pvtu", f)[0]))


def top_view(points):
    """{(i, j): largest damage} on the grid of spacing h (the plate's lower
    edge at y = -20 mm), and h. Where the plate is not peridynamic the
    picture stays empty."""
    ys = sorted({round(p[1] * 1e7) for p in points})
    h = min(b - a for a, b in zip(ys, ys[1:])) * 1e-7
    image = {}
    for x, y, d in points:
        key = (int(x / h), int((y + 0.02) / h))
        image[key] = max(image.get(key, 0.0), d)
    return image, h


def draw_top_view(ax, image, h):
    """The top view on the plate 100 x 40 mm (nan: not peridynamic)."""
    nx, ny = round(0.1 / h), round(0.04 / h)
    grid = [[float("nan")] * nx for _ in range(ny)]
    for (i, j), d in image.items():
        if 0 <= i < nx and 0 <= j < ny:
            grid[j][i] = d
    ax.imshow(grid, origin="lower", extent=(0, 100, -20, 20), cmap="jet", vmin=0, vmax=1, interpolation="nearest")
