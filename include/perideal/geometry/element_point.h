#pragma once
// A first-order 3D element of a mesh file as one peridynamic point: its exact
// volume and volume-weighted centroid, after the checks that it is a valid
// cell. Shared by the readers that make points of cells p4est cannot hold
// (Gmsh with Cells as points, Exodus).

#include <perideal/geometry/point_cubes.h>

#include <deal.II/base/point.h>

#include <string>
#include <vector>

namespace perideal
{
  /// The first-order 3D shapes. Gmsh and Exodus II number their corners the
  /// same way: a hexahedron's bottom face 0-1-2-3 then the top face 4-5-6-7
  /// above it, a prism's triangles 0-1-2 and 3-4-5, a pyramid's base 0-1-2-3
  /// and apex 4.
  enum class ElementShape
  {
    tetrahedron,
    hexahedron,
    prism,
    pyramid
  };

  /// "tetrahedron", ...
  std::string
  shape_name(const ElementShape shape);

  /// 4, 8, 6, 5.
  unsigned int
  n_corners(const ElementShape shape);

  /// The element of corners @p p (in the order above) as a point of block
  /// @p block: its exact volume and volume-weighted centroid (hexahedra,
  /// prisms and pyramids as trilinear maps, whose faces need not be planar).
  /// Refuses (AssertThrow, a message beginning with @p element, naming the
  /// node of @p node_numbers where the Jacobian is worst; @p scaled adds
  /// "(after Scale)") an element whose volume or Jacobian is zero or negative
  /// at a corner or inside: flat, inverted or tangled, or numbered against
  /// the order above.
  CloudPoint
  element_as_point(const ElementShape               shape,
                   const std::vector<dealii::Point<dim>> &p,
                   const std::vector<long>         &node_numbers,
                   const std::string               &element,
                   const bool                       scaled,
                   const unsigned int               block);
} // namespace perideal
