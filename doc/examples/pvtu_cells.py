"""Reading a run's output without VTK, for the examples' analysis scripts
(kalthoff_winkler/analyze.py, crack_branching/analyze.py).

  read_cells(pvtu, field)  every cell of a .pvtu's pieces: (x, y, z, value, width),
                           its centre (the 8 vertices averaged), the field's
                           value (cell data written per vertex) and its extent
                           along x: each PD point is a cell, and the finest
                           cells are the PD points
  log_value(log, key)      a line '  key: value' of a pd_app log (the summary)
"""

import base64
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
