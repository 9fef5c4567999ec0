#pragma once
// Discretization/Gmsh/Cells as points: the 3D cells of a Gmsh mesh, of any
// shape p4est cannot hold, as peridynamic points (one per cell, at its
// centroid, with its volume), made into cubes like a Text file's points.

#include <perideal/geometry/point_cubes.h>

#include <string>
#include <vector>

namespace perideal
{
  struct GmshCellPoint
  {
    long       tag; // Gmsh's element number
    CloudPoint point;
  };

  /// Every first-order 3D element of the Gmsh file @p file (ASCII, format
  /// 2.2 or 4.1: tetrahedra, hexahedra, prisms, pyramids, in any mix), with
  /// its coordinates times @p scale, as one point: the element's exact volume
  /// and volume-weighted centroid (of its trilinear map for hexahedra, prisms
  /// and pyramids, whose faces need not be planar), its physical group as
  /// the block. Lower-dimensional elements are skipped. Refuses (AssertThrow,
  /// naming the file and the element's number) a file it cannot read, one
  /// without 3D elements, second-order elements, and elements whose Jacobian
  /// is zero or negative at a corner or inside (flat, inverted or tangled
  /// cells, or nodes numbered against Gmsh's order).
  std::vector<GmshCellPoint>
  gmsh_cells_as_points(const std::string &file, const double scale);
} // namespace perideal
