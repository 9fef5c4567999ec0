#!/usr/bin/env python3
"""Compares the Exodus II output of a run (Output/Field format = exodus)
with the HDF5 + XDMF files of the same run (Field format = hdf5), reading
the Exodus file with netCDF4, not with the Exodus library pd_app writes it
with. Checks, at every step: the same times (bit for bit); a SPHERE element
(one node) for every PD cell of the HDF5 files, its node at the cell's
centre, and a HEX8 for every FE cell with the cell's 8 vertices in the same
order; every field as Peridigm names it (a vector's components NAMEX,
NAMEY, NAMEZ as nodal variables, or element variables; a tensor's NAMEXX,
NAMEXY, ...): a point's value equal to its HDF5 cell's bit for bit (or
within --rtol), an element variable equal to its cell's, and an FE cell's
nodal variable averaged over its 8 vertices equal to the HDF5 value at the
cell's centre within --rtol-fe; unique node and element ids; and, with
--globals, the global variables equal to the globals CSV's row of the same
time. A file of a decomposed run (Exodus files = per rank) is read from
all its pieces RUN.e.N.r. A run whose written cells change (Adaptivity)
writes a series, RUN.e, RUN.e-s0002, ...: every file of it is read, its
steps the next ones of the .xdmf.

    compare_exodus.py RUN.e RUN.xdmf [--pieces N] [--globals RUN.globals.csv]
                      [--rtol 0] [--rtol-fe 1e-14] [--precision double|float]

Prints each check and PASS/FAIL; exit status 1 on a failure."""

import argparse
import csv
import os
import sys

import netCDF4
import numpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from compare_vtu import Checks, centre_key  # noqa: E402
from compare_xdmf import xdmf_steps  # noqa: E402


def names(nc, variable):
    if variable not in nc.variables:
        return []
    return [str(name).strip() for name in netCDF4.chartostring(nc.variables[variable][:])]


def read_piece(path):
    """One Exodus file as plain arrays (netCDF4 only)."""
    nc = netCDF4.Dataset(path)
    nc.set_auto_mask(False)
    piece = {"coordinates": numpy.stack([nc.variables["coord" + a][:] for a in "xyz"], axis=1),
             "node_ids": nc.variables["node_num_map"][:] if "node_num_map" in nc.variables else None,
             "times": nc.variables["time_whole"][:],
             "blocks": [], "nodal": {}, "global": {},
             "types": {nc.variables[v].dtype for v in nc.variables if v.startswith("vals_")}}
    ids = nc.variables["eb_prop1"][:]
    block_names = names(nc, "eb_names")
    element_names = names(nc, "name_elem_var")
    first = 0
    for b, block_id in enumerate(ids):
        connect = nc.variables.get("connect%d" % (b + 1))
        n = connect.shape[0] if connect is not None else 0
        block = {"id": int(block_id), "name": block_names[b],
                 "type": connect.getncattr("elem_type") if connect is not None else "",
                 "connect": (connect[:] - 1) if n else numpy.zeros((0, 1), int),
                 "element_ids": nc.variables["elem_num_map"][first:first + n] if n else [],
                 "values": {}}
        for v, name in enumerate(element_names):
            key = "vals_elem_var%deb%d" % (v + 1, b + 1)
            if key in nc.variables:
                block["values"][name] = nc.variables[key][:]
        piece["blocks"].append(block)
        first += n
    for v, name in enumerate(names(nc, "name_nod_var")):
        piece["nodal"][name] = nc.variables["vals_nod_var%d" % (v + 1)][:]
    for v, name in enumerate(names(nc, "name_glo_var")):
        piece["global"][name] = nc.variables["vals_glo_var"][:, v]
    nc.close()
    return piece


def component_names(field, columns):
    """Peridigm's names: Force density -> Force_DensityX, ..."""
    base = {"Block": "Block_Id", "Rank": "Proc_Num"}.get(field) or "_".join(
        w[:1].upper() + w[1:] for w in field.split(" "))
    if columns == 1:
        return [base]
    if columns == 3:
        return [base + a for a in "XYZ"]
    return [base + a + b for a in "XYZ" for b in "XYZ"]


def compare_file(check, pieces, steps, first_step, kind, args):
    """One file of the series (all its pieces) against the .xdmf's steps
    from first_step on; returns the step after its last."""
    check("every variable is %s" % kind.__name__, all(p["types"] <= {numpy.dtype(kind)} for p in pieces))
    times = pieces[0]["times"]
    mine = steps[first_step:first_step + len(times)]
    check("%d steps from the .xdmf's step %d; the times bit for bit (as %s)"
          % (len(times), first_step + 1, kind.__name__),
          len(times) == len(mine) and all(p["times"].tolist() == times.tolist() for p in pieces)
          and all(t == kind(s[0]) for t, s in zip(times, mine)))
    node_ids = numpy.concatenate([p["node_ids"] for p in pieces])
    element_ids = numpy.concatenate([b["element_ids"] for p in pieces for b in p["blocks"] if len(b["element_ids"])])
    check("%d node ids, %d element ids, each unique" % (len(node_ids), len(element_ids)),
          len(set(node_ids.tolist())) == len(node_ids) and len(set(element_ids.tolist())) == len(element_ids))
    check("every element block is SPHERE or HEX8, the same in every piece",
          all(b["type"] in ("SPHERE", "HEX8", "") for p in pieces for b in p["blocks"])
          and all([b["id"] for b in p["blocks"]] == [b["id"] for b in pieces[0]["blocks"]] for p in pieces))

    for k, (time, cells, fields, _) in enumerate(mine):
        print("step %d (time %.17g):" % (first_step + k + 1, time))
        key = centre_key(min(numpy.abs(c[0] - c[1]).max() for c in cells))
        by_centre = {key(c): c_index for c_index, c in enumerate(cells)}
        matched, vertices_equal, worst, scale = 0, True, {}, {}

        def compare(name, a, b):
            scale[name] = max(scale.get(name, 0.0), float(numpy.abs(b).max()))
            worst[name] = max(worst.get(name, 0.0), float(numpy.abs(numpy.asarray(a, float) - b).max()))

        for p in pieces:
            for block in p["blocks"]:
                for e, nodes in enumerate(block["connect"]):
                    xyz = p["coordinates"][nodes]
                    corners = xyz if len(nodes) == 8 else numpy.repeat(xyz, 8, axis=0)
                    c_index = by_centre.get(key(corners))
                    if c_index is None:
                        continue
                    matched += 1
                    sphere = len(nodes) == 1
                    if not sphere:
                        vertices_equal &= numpy.array_equal(numpy.asarray(xyz, float), cells[c_index])
                    for field, values in fields.items():
                        columns = values.shape[1]
                        components = component_names(field, columns)
                        if all(c in block["values"] for c in components):
                            compare(field, [block["values"][c][k][e] for c in components], values[c_index])
                        elif all(c in p["nodal"] for c in components):
                            at_nodes = numpy.array([[p["nodal"][c][k][n] for c in components] for n in nodes])
                            compare(field + (" (point)" if sphere else " (FE vertices' mean)"),
                                    at_nodes.mean(axis=0), values[c_index])
                        else:
                            compare(field + " (missing)", [numpy.inf] * columns, values[c_index])
        check("%d elements, each at one of the %d HDF5 cells" % (matched, len(cells)), matched == len(cells))
        check("every HEX8's vertices are its cell's, in order", vertices_equal)
        for name in sorted(worst):
            rtol = args.rtol_fe if "vertices" in name else args.rtol
            diff = worst[name] / max(scale[name], 1e-300)
            check("'%s': largest |exodus - hdf5| / max |hdf5| = %.3g <= %g" % (name, diff, rtol), diff <= rtol)

    return first_step + len(times)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("exodus")
    parser.add_argument("xdmf")
    parser.add_argument("--pieces", type=int, default=0)
    parser.add_argument("--globals")
    parser.add_argument("--rtol", type=float, default=0.0)
    parser.add_argument("--rtol-fe", type=float, default=1e-14)
    parser.add_argument("--precision", choices=("double", "float"), default="double")
    args = parser.parse_args()
    check = Checks()

    def piece_paths(base):
        if not args.pieces:
            return [base]
        width = len(str(args.pieces))
        return ["%s.%d.%0*d" % (base, args.pieces, width, r) for r in range(args.pieces)]

    # The series: RUN.e, then RUN.e-s0002, ... as long as they exist.
    series = [args.exodus]
    while os.path.exists(piece_paths("%s-s%04d" % (args.exodus, len(series) + 1))[0]):
        series.append("%s-s%04d" % (args.exodus, len(series) + 1))
    kind = numpy.float64 if args.precision == "double" else numpy.float32
    steps, problems = xdmf_steps(args.xdmf)
    check("the .xdmf reads", not problems and len(steps) > 0)
    first_step = 0
    all_times, all_globals = [], {}
    for base in series:
        paths = piece_paths(base)
        check("the files %s exist" % ", ".join(os.path.basename(p) for p in paths), all(map(os.path.exists, paths)))
        pieces = [read_piece(p) for p in paths]
        first_step = compare_file(check, pieces, steps, first_step, kind, args)
        all_times += pieces[0]["times"].tolist()
        for name, values in pieces[0]["global"].items():
            all_globals.setdefault(name, []).extend(values.tolist())
    check("%d steps in %d Exodus file%s, %d in the .xdmf" % (first_step, len(series), "s" if len(series) > 1 else "",
                                                          len(steps)), first_step == len(steps))

    if args.globals:
        with open(args.globals) as f:
            rows = list(csv.DictReader(f))
        by_time = {float(r["time"]): r for r in rows}
        glob = all_globals
        columns = [c for c in rows[0] if c not in ("step", "time")]
        check("the global variables are the CSV's columns %s" % columns, list(glob) == columns)
        written = [k for k, t in enumerate(all_times) if float(t) in by_time]
        check("%d of %d steps have a globals row" % (len(written), len(all_times)), len(written) > 0)
        equal = all(len(glob[c]) == len(all_times) and float(glob[c][k]) == float(by_time[float(all_times[k])][c])
                    for k in written for c in columns if c in glob)
        check("each global variable equals the CSV's value bit for bit", equal)
    return check.finish()


if __name__ == "__main__":
    sys.exit(main())
