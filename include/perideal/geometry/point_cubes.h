#pragma once
// A point cloud as a coarse mesh (Discretization/Text file, and Gmsh with
// Cells as points): each point a cube of its volume centred on it, one coarse
// cell of its own, whose centroid and measure are the point's position and
// volume and whose material id is its block. Regions, conditions, families
// and output then work on a point cloud as on a mesh.

#include <perideal/base/input.h>

#include <deal.II/base/point.h>
#include <deal.II/grid/tria.h>

#include <vector>

namespace perideal
{
  struct CloudPoint
  {
    dealii::Point<dim> x;
    double             volume; // > 0
    unsigned int       block;  // the cell's material id
  };

  /// The order of a Morton curve through @p points: the coarse cell c that
  /// create_point_cubes() makes is point morton_order(points)[c].
  std::vector<unsigned int>
  morton_order(const std::vector<CloudPoint> &points);

  /// Creates the cubes of @p points on @p tria in the order of a Morton
  /// curve through them, so that each rank's share is compact in space
  /// (p4est partitions the coarse cells in their order). Cubes whose corners
  /// coincide to the bit (a lattice of points) share those vertices.
  void
  create_point_cubes(dealii::Triangulation<dim> &tria, const std::vector<CloudPoint> &points);
} // namespace perideal
