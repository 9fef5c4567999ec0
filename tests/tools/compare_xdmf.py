#!/usr/bin/env python3
"""Compares the HDF5 + XDMF field files of a run (Output/Field format =
hdf5) with the VTU files of the same run (Field format = vtu), on any
numbers of ranks: the same steps at the same times; at every step the same
cells (matched by their centres) with their 8 vertices in the same (VTK)
order, the same fields with the same components, and each HDF5 value (a
cell's) equal to the mean of the VTU's 8 vertex values (the cell's value for
a point; for a Q1 FE cell's nodal field the value at its centre) within
RTOL of the field's largest magnitude. Checks that every dataset the .xdmf
names exists with the dimensions and the number type it states, that the
datasets are Float64 or Float32 as --precision says, and that a field of 9
components is not declared a Tensor (ParaView would transpose it).

    compare_xdmf.py RUN.pvd RUN.xdmf [--rtol 1e-12] [--precision double|float]

Prints each check and PASS/FAIL; exit status 1 on a failure."""

import argparse
import os
import re
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_vtu import Checks, centre_key, cells as vtu_cells  # noqa: E402


def dataset(folder, item, failures):
    """The array a DataItem names, after checking its dimensions and type."""
    file, path = item.text.strip().split(":", 1)
    with h5py.File(os.path.join(folder, file), "r") as h5:
        data = h5[path][()]
    dims = tuple(int(d) for d in item.get("Dimensions").split())
    kind = {("Float", "8"): numpy.float64, ("Float", "4"): numpy.float32,
            ("UInt", "4"): numpy.uint32}[(item.get("NumberType"), item.get("Precision"))]
    if data.shape != dims or data.dtype != kind:
        failures.append("%s: %s %s in the file, %s %s in the .xdmf"
                        % (item.text.strip(), data.shape, data.dtype, dims, kind.__name__))
    return data


def xdmf_steps(xdmf):
    """[(time, cells, {name: values}, types)] of the series: cells as
    [8 vertices' coordinates], values as [n_cells x components]."""
    folder = os.path.dirname(xdmf)
    root = ET.parse(xdmf).getroot()
    steps, failures = [], []
    for grid in root.find("Domain").find("Grid").findall("Grid"):
        time = float(grid.find("Time").get("Value"))
        topology = dataset(folder, grid.find("Topology").find("DataItem"), failures)
        nodes = dataset(folder, grid.find("Geometry").find("DataItem"), failures)
        fields, types = {}, {}
        for attribute in grid.findall("Attribute"):
            item = attribute.find("DataItem")
            fields[attribute.get("Name")] = dataset(folder, item, failures)
            # ParaView's XDMF Reader transposes a Tensor or Matrix: the
            # components would not be in the VTU files' (row-major) order.
            columns = fields[attribute.get("Name")].shape[1]
            expected = "Vector" if columns == 3 else "Scalar"
            if attribute.get("AttributeType") != expected:
                failures.append("'%s' (%d components) is declared %s, not %s"
                                % (attribute.get("Name"), columns, attribute.get("AttributeType"), expected))
            types[attribute.get("Name")] = item.get("Precision")
        steps.append((time, nodes[topology], fields, types))
    return steps, failures


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("pvd")
    parser.add_argument("xdmf")
    parser.add_argument("--rtol", type=float, default=1e-12)
    parser.add_argument("--precision", choices=("double", "float"), default="double")
    args = parser.parse_args()
    check = Checks()

    folder = os.path.dirname(args.pvd)
    records = [(float(t), os.path.join(folder, f))
               for t, f in re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', open(args.pvd).read())]
    steps, problems = xdmf_steps(args.xdmf)
    for p in problems:
        print("  " + p)
    check("every dataset the .xdmf names has its dimensions and number type", not problems)
    check("%d steps in the .pvd, %d in the .xdmf" % (len(records), len(steps)),
          len(records) == len(steps) and len(steps) > 0)
    precision = "8" if args.precision == "double" else "4"
    for (time, pvtu), (h5_time, h5_cells, fields, types) in zip(records, steps):
        print(os.path.basename(pvtu) + ":")
        # The .pvd's times have 6 digits (deal.II's writer).
        check("time %.17g against the .pvd's %g" % (h5_time, time), abs(h5_time - time) <= 1e-5 * max(abs(time), 1e-300))
        check("every field is Float%s" % ("64" if precision == "8" else "32"),
              all(p == precision for p in types.values()))
        vtu, vtu_types = vtu_cells(pvtu)
        check("%d cells in the VTU files, %d in the HDF5 file" % (len(vtu), len(h5_cells)),
              len(vtu) == len(h5_cells) > 0)
        check("the same fields with the same components",
              {n: t[1] for n, t in vtu_types.items()} == {n: v.shape[1] for n, v in fields.items()})
        key = centre_key(min(numpy.abs(c[0] - c[1]).max() for c in h5_cells))
        by_centre = {key(c): k for k, c in enumerate(h5_cells)}
        check("every cell's centre is in both", len(by_centre) == len(h5_cells)
              and all(key(xyz) in by_centre for xyz, _ in vtu))
        scale, worst = {}, {}
        for xyz, values in vtu:
            k = by_centre.get(key(xyz))
            if k is None:
                continue
            pairs = [("Points", numpy.array(xyz).ravel(), h5_cells[k].ravel())]
            pairs += [(n, numpy.mean(numpy.array(v), axis=0), fields[n][k]) for n, v in values.items() if n in fields]
            for name, a, b in pairs:
                scale[name] = max(scale.get(name, 0.0), numpy.abs(a).max())
                worst[name] = max(worst.get(name, 0.0), numpy.abs(a - b).max())
        check.differences(worst, scale, args.rtol, "|hdf5 - vtu| / max |vtu|")
    return check.finish()


if __name__ == "__main__":
    sys.exit(main())
