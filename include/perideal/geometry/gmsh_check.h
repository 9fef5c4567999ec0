#pragma once
// The checks of a Gmsh mesh file before deal.II reads it.

#include <string>

namespace perideal
{
  /// Refuses (AssertThrow, a message naming the element and the fix) a Gmsh
  /// mesh that p4est cannot take or whose cells are invalid: elements that are
  /// not first-order hexahedra are refused, not converted (p4est, the
  /// refinement and the continuum blocks need hexahedra, and Gmsh makes an
  /// all-hexahedral mesh of any geometry with Mesh.SubdivisionAlgorithm = 2),
  /// as are cells smaller than round-off at @p scale and inverted or tangled
  /// ones. Does nothing for a file it cannot parse: deal.II's reader says why.
  /// With @p extruded (Discretization/Gmsh/Extrusion thickness), the file
  /// must instead be a 2D mesh of first-order quadrilaterals in the plane
  /// z = 0, which become the hexahedra of the extrusion.
  void
  check_gmsh_cells(const std::string &file, const double scale, const bool extruded = false);
} // namespace perideal
