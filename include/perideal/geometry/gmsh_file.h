#pragma once
// A Gmsh mesh file as the user wrote it: its nodes and elements, read before
// (or instead of) deal.II's reader, which inverts left-handed cells, reorders
// vertices and takes hexahedra only; and the trilinear map of a hexahedron.

#include <perideal/base/input.h>

#include <deal.II/base/point.h>

#include <array>
#include <map>
#include <string>
#include <vector>

namespace perideal
{
  struct GmshMesh
  {
    std::map<long, dealii::Point<dim>> nodes;
    struct Element
    {
      long              tag;
      int               type;     // Gmsh's element type: 4 tetrahedron, 5 hexahedron, ...
      long              physical; // its physical group, 0 if none (deal.II's material id)
      std::vector<long> nodes;
    };
    std::vector<Element> elements;
  };

  /// Reads the nodes and elements of an ASCII .msh file, format 2.2 or 4.1,
  /// into @p mesh. false if the file is something else (binary, another
  /// version, not well formed).
  bool
  read_gmsh_file(const std::string &file, GmshMesh &mesh);

  /// The Jacobian determinant of the trilinear map of a hexahedron with the
  /// vertices @p v in deal.II's lexicographic order, at the reference point
  /// @p t in [0, 1]^3 (a corner when every t[d] is 0 or 1).
  double
  hex_jacobian(const std::array<dealii::Point<dim>, 8> &v, const std::array<double, 3> &t);
} // namespace perideal
