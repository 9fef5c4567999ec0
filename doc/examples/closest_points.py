"""How close the points of a PeriDeal run come to each other, snapshot by snapshot.

  pvpython closest_points.py RUN.pvd DISTANCE

For every snapshot of the .pvd series: the points' current positions (each
cell's centre moved by its Displacement), the smallest distance between two
of them, and the number of pairs closer than DISTANCE (in the run's length
unit). Bodies or fragments that pass through each other give pairs far
closer than the point spacing; with contact on, no pair comes much closer
than the contact radius allows (doc/contact.md). The run must write
Displacement. Needs ParaView's Python (pvpython, package python3-paraview),
which brings numpy and scipy.
"""

import argparse
import os
import xml.etree.ElementTree as ElementTree

from scipy.spatial import cKDTree
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLPUnstructuredGridReader

parser = argparse.ArgumentParser(
    description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("pvd")
parser.add_argument("distance", type=float)
args = parser.parse_args()

if not os.path.isfile(args.pvd):
    raise SystemExit("Error: cannot open '%s'" % args.pvd)
if args.distance <= 0:
    raise SystemExit("Error: DISTANCE must be positive")
folder = os.path.dirname(os.path.abspath(args.pvd))
snapshots = [(float(d.get("timestep")), os.path.join(folder, d.get("file")))
             for d in ElementTree.parse(args.pvd).getroot().iter("DataSet")]

print("time, points, smallest distance, pairs closer than %g" % args.distance)
for time, name in snapshots:
    reader = vtkXMLPUnstructuredGridReader()
    reader.SetFileName(name)
    reader.Update()
    grid = reader.GetOutput()
    displacement = grid.GetPointData().GetArray("Displacement")
    if displacement is None:
        raise SystemExit("Error: %s has no Displacement field" % name)
    # Every cell holds one point; its fields are written at its 8 vertices.
    vertices = vtk_to_numpy(grid.GetPoints().GetData()).reshape(-1, 8, 3)
    u = vtk_to_numpy(displacement).reshape(-1, 8, 3)
    y = vertices.mean(axis=1) + u[:, 0, :]
    tree = cKDTree(y)
    nearest, _ = tree.query(y, k=2)
    print("%.6g, %d, %.4g, %d" % (time, len(y), nearest[:, 1].min(),
                                  len(tree.query_pairs(args.distance))))
