#pragma once
// A Gmsh mesh file as the user wrote it: its nodes and elements, read before
// (or instead of) deal.II's reader, which inverts left-handed cells, reorders
// vertices and takes hexahedra only.

#include <perideal/base/input.h>
#include <perideal/geometry/hexahedron.h>

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
} // namespace perideal
