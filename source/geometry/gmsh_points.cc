// The 3D cells of a Gmsh mesh as peridynamic points (see gmsh_points.h),
// each made a point by element_as_point() (element_point.h).

#include <perideal/geometry/element_point.h>
#include <perideal/geometry/gmsh_file.h>
#include <perideal/geometry/gmsh_points.h>

#include <deal.II/base/exceptions.h>

namespace perideal
{
  using namespace dealii;

  std::vector<GmshCellPoint>
  gmsh_cells_as_points(const std::string &file, const double scale)
  {
    const std::string where = "Discretization/Gmsh/Mesh file '" + file + "'";
    GmshMesh          mesh;
    AssertThrow(read_gmsh_file(file, mesh),
                ExcMessage(where + " cannot be read as an ASCII Gmsh mesh of format 2.2 or 4.1 "
                                   "(Discretization/Gmsh/Cells as points reads no other): save it from Gmsh "
                                   "with -format msh22 or msh41, not binary"));
    std::vector<GmshCellPoint> points;
    for (const auto &e : mesh.elements)
      {
        ElementShape shape;
        bool         second_order = false;
        switch (e.type)
          {
            case 4: shape = ElementShape::tetrahedron; break;
            case 5: shape = ElementShape::hexahedron; break;
            case 6: shape = ElementShape::prism; break;
            case 7: shape = ElementShape::pyramid; break;
            case 11: case 29: case 30: case 31: shape = ElementShape::tetrahedron, second_order = true; break;
            case 12: case 17: case 92: case 93: shape = ElementShape::hexahedron, second_order = true; break;
            case 13: case 18: case 90: case 91: shape = ElementShape::prism, second_order = true; break;
            case 14: case 19: case 118: case 119: shape = ElementShape::pyramid, second_order = true; break;
            default: continue; // surfaces, curves and points are no cells
          }
        const unsigned int n_nodes = n_corners(shape);
        const std::string element = where + ": element " + std::to_string(e.tag) + " (a " + shape_name(shape) + ")";
        AssertThrow(!second_order,
                    ExcMessage(element + " is of higher order (Gmsh element type " + std::to_string(e.type) +
                               "): Cells as points reads first-order elements only (their corners make the "
                               "cell): mesh with Mesh.ElementOrder = 1 (gmsh -order 1)"));
        AssertThrow(e.nodes.size() == n_nodes,
                    ExcMessage(element + " has " + std::to_string(e.nodes.size()) + " nodes instead of " +
                               std::to_string(n_nodes)));
        AssertThrow(e.physical >= 0 && e.physical < long(numbers::invalid_material_id),
                    ExcMessage(element + ": its physical group " + std::to_string(e.physical) +
                               " is not a valid block number (a whole number >= 0)"));
        std::vector<Point<dim>> p(n_nodes);
        for (unsigned int i = 0; i < n_nodes; ++i)
          {
            const auto it = mesh.nodes.find(e.nodes[i]);
            AssertThrow(it != mesh.nodes.end(),
                        ExcMessage(element + " has the node " + std::to_string(e.nodes[i]) +
                                   ", which the file does not define"));
            p[i] = scale * it->second;
          }
        points.push_back({e.tag, element_as_point(shape, p, e.nodes, element, scale != 1, e.physical)});
      }
    AssertThrow(!points.empty(),
                ExcMessage(where + " holds no 3D elements (tetrahedra, hexahedra, prisms or pyramids): "
                                   "mesh the volume (gmsh -3)"));
    return points;
  }
} // namespace perideal
