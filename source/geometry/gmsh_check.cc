// The checks of a Gmsh mesh before deal.II reads it (Discretization/Gmsh):
// the file is read as the user wrote it, since deal.II inverts left-handed
// cells and reorders vertices, and p4est crashes on cells that are not
// hexahedra.

#include <perideal/base/input.h>
#include <perideal/geometry/gmsh_check.h>
#include <perideal/geometry/gmsh_file.h>

#include <deal.II/base/point.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <vector>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    std::string
    point_string(const Point<dim> &p)
    {
      std::ostringstream s;
      s << std::setprecision(6) << '(' << p[0] << ' ' << p[1] << ' ' << p[2] << ')';
      return s.str();
    }

    std::string
    to_string_short(const double x)
    {
      std::ostringstream s;
      s << std::setprecision(6) << x;
      return s.str();
    }
  } // namespace

  void
  check_gmsh_cells(const std::string &file, const double scale, const bool extruded)
  {
    GmshMesh mesh;
    if (!read_gmsh_file(file, mesh))
      return;
    const std::string where = "Discretization/Gmsh/Mesh file '" + file + "'";
    unsigned long     tets = 0, prisms = 0, pyramids = 0, hexes = 0, curved = 0, triangles = 0, quads = 0;
    for (const auto &e : mesh.elements)
      switch (e.type)
        {
          case 4: case 11: case 29: case 30: case 31: ++tets; break;
          case 5: ++hexes; break;
          case 12: case 17: case 92: case 93: ++curved; break;
          case 6: case 13: case 18: case 90: case 91: ++prisms; break;
          case 7: case 14: case 19: case 118: case 119: ++pyramids; break;
          case 2: case 9: case 20: case 21: case 22: case 23: case 24: case 25: ++triangles; break;
          case 3: case 10: case 16: case 36: case 37: ++quads; break;
          default: break;
        }
    const std::string make_hexahedra =
      "make an all-hexahedral first-order mesh in Gmsh: add 'Mesh.SubdivisionAlgorithm = 2;' "
      "(every cell split into hexahedra) or build a structured mesh (Transfinite Volume and "
      "Recombine, or Extrude with Layers and Recombine); 'Mesh.RecombineAll = 1; "
      "Mesh.Recombine3DAll = 1;' may leave tetrahedra";
    if (extruded)
      {
        const unsigned long curved_quads = quads - std::count_if(mesh.elements.begin(), mesh.elements.end(),
                                                                 [](const auto &e) { return e.type == 3; });
        AssertThrow(tets + prisms + pyramids + hexes + curved == 0,
                    ExcMessage(where + " holds volume cells: Discretization/Gmsh/Extrusion thickness extrudes "
                               "a 2D mesh (gmsh -2); set it to 0 for a 3D mesh"));
        AssertThrow(quads > 0 && triangles == 0 && curved_quads == 0,
                    ExcMessage(where + " holds " + std::to_string(triangles) + " triangles, " +
                               std::to_string(quads - curved_quads) + " first-order and " +
                               std::to_string(curved_quads) + " second-order quadrilaterals: only first-order "
                               "quadrilaterals extrude into hexahedra; recombine the surface in Gmsh ('Recombine "
                               "Surface{...};' or 'Mesh.RecombineAll = 1;', with 'Mesh.SubdivisionAlgorithm = 1;' "
                               "for no triangle left)"));
        for (const auto &[tag, p] : mesh.nodes)
          AssertThrow(p[2] == 0 && std::isfinite(scale * p.norm()),
                      ExcMessage(where + ": node " + std::to_string(tag) + " at " + point_string(p) +
                                 (p[2] != 0 ? " is not in the plane z = 0, which Extrusion thickness extrudes "
                                              "along z: mesh the section there" :
                                              " times Discretization/Gmsh/Scale is not a finite point")));
        return; // deal.II's reader checks the quadrilaterals
      }
    AssertThrow(tets + prisms + pyramids + hexes + curved > 0,
                ExcMessage(where + " holds no volume cells (" + std::to_string(triangles) +
                           " triangles, " + std::to_string(quads) +
                           " quadrilaterals): a 2D mesh; PeriDeal needs a 3D mesh of hexahedra: "
                           "mesh the volume (gmsh -3) and " + make_hexahedra));
    if (tets + prisms + pyramids + curved > 0)
      {
        std::string list;
        for (const auto &[n, what] : std::vector<std::pair<unsigned long, std::string>>{
               {tets, "tetrahedra"}, {prisms, "prisms"}, {pyramids, "pyramids"},
               {curved, "second-order hexahedra"}})
          if (n > 0)
            list += std::to_string(n) + " " + what + ", ";
        // Peridynamic blocks can take the other cells as points instead.
        const std::string as_points =
          tets + prisms + pyramids > 0 ?
            ". For peridynamic blocks, Discretization/Gmsh/Cells as points = true reads each first-order "
            "cell as one point instead (its centroid and volume)" :
            "";
        AssertThrow(false,
                    ExcMessage(where + " holds " + list + std::to_string(hexes) +
                               " hexahedra: only first-order hexahedra can be used (p4est "
                               "and the refinement work on hexahedra): " + make_hexahedra + as_points));
      }

    // The coordinates the run uses (times Scale) must be finite.
    for (const auto &[tag, p] : mesh.nodes)
      AssertThrow(std::isfinite(scale * p.norm()),
                  ExcMessage(where + ": node " + std::to_string(tag) + " at " + point_string(p) +
                             " times Discretization/Gmsh/Scale (" + to_string_short(scale) +
                             ") is not a finite point"));

    // deal.II's vertex order from Gmsh's: Gmsh goes around each face.
    constexpr std::array<unsigned int, 8> gmsh_vertex = {{0, 1, 3, 2, 4, 5, 7, 6}};
    unsigned long bad = 0, hex_index = 0, first_index = 0;
    long          first_tag = 0, first_node = 0;
    Point<dim>    first_centroid;
    double        first_value = 0, first_volume = 0;
    for (const auto &e : mesh.elements)
      {
        if (e.type != 5)
          continue;
        ++hex_index;
        AssertThrow(e.nodes.size() == 8,
                    ExcMessage(where + ": element " + std::to_string(e.tag) + " is a hexahedron with " +
                               std::to_string(e.nodes.size()) + " nodes instead of 8"));
        std::array<Point<dim>, 8> v;
        Point<dim>                centroid;
        for (unsigned int c = 0; c < 8; ++c)
          {
            const auto it = mesh.nodes.find(e.nodes[gmsh_vertex[c]]);
            if (it == mesh.nodes.end())
              return; // an undefined node: deal.II's reader reports it
            v[c] = it->second;
            centroid += v[c] / 8;
          }
        // Of one sign in a valid cell (negative: numbered left-handed, which
        // deal.II inverts), whose volume is then the Gauss points' mean.
        const HexJacobians J      = hex_jacobians(v);
        const auto        &corner = J.corner;
        const double       volume = J.volume;
        if (J.one_sign)
          continue;
        if (++bad == 1)
          {
            first_tag      = e.tag;
            first_index    = hex_index;
            first_centroid = centroid;
            first_volume   = volume;
            // The corner to name: one against the volume's sign, or the
            // smallest.
            unsigned int worst = 0;
            for (unsigned int c = 1; c < 8; ++c)
              if ((volume >= 0 ? corner[c] : -corner[c]) < (volume >= 0 ? corner[worst] : -corner[worst]))
                worst = c;
            first_node  = e.nodes[gmsh_vertex[worst]];
            first_value = corner[worst];
          }
      }
    AssertThrow(bad == 0,
                ExcMessage(where + ": " + std::to_string(bad) + " of " + std::to_string(hexes) +
                           " hexahedra are invalid (the Jacobian is zero or changes sign in the "
                           "cell: a twisted, folded, overlapping or flat cell, or a wrong node "
                           "order); the first is element " + std::to_string(first_tag) +
                           " (hexahedron " + std::to_string(first_index) + " in the file) at " +
                           point_string(first_centroid) +
                           (scale != 1 ? " (the file's coordinates, before Scale)" : "") +
                           ", volume " + to_string_short(first_volume) + ", Jacobian " +
                           to_string_short(first_value) + " at its node " + std::to_string(first_node) +
                           ": fix the mesh, e.g. move its nodes back or untangle it in Gmsh"));
  }
} // namespace perideal
