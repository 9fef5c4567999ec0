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
  void
  check_gmsh_cells(const std::string &file, const double scale);
} // namespace perideal
