#pragma once
// Partial volumes: the share of a neighbor's cell inside the horizon sphere.
//
// A PD point stands for its whole cell. With one-point quadrature a neighbor
// counts fully if its centroid is within the horizon and not at all
// otherwise, which makes the family sums (weighted volume, micromodulus
// calibration) jump as delta/h changes. With partial volumes a bond i-j
// carries beta_ij = (|C_j ∩ B(x_i, delta_i)| / V_j + |C_i ∩ B(x_j, delta_j)| / V_i) / 2,
// from the cells' real geometry (trilinear hexahedra): symmetric, so both
// owners of a bond use the same number and action equals reaction.

#include <perideal/discretization/point_cloud.h>
#include <perideal/neighborhood/bonds.h>

#include <deal.II/base/point.h>

#include <vector>

namespace perideal
{
  /// The volume of the trilinear hexahedron with the 8 @p vertices (x, y, z
  /// each, deal.II's lexicographic order) inside the ball (@p center,
  /// @p radius): adaptive bisection in reference coordinates down to 1/8 of
  /// the cell; the last sub-cells cut by the sphere's tangent plane.
  double
  volume_in_ball(const double *vertices, const dealii::Point<dim> &center, const double radius);

  /// Sets bonds.volume_fraction to beta_ij for every bond (needs
  /// cloud.cell_vertices of owned and ghost points, and families found with
  /// the reach grown by the largest cell radius) and drops the bonds with
  /// beta_ij = 0.
  void
  compute_partial_volumes(const PointCloud &cloud, Bonds &bonds, const std::vector<double> &block_horizon);
} // namespace perideal
