#pragma once
// The rigid-body motions a set of prescribed displacement entries leaves
// free. A motion u(x) = t + w x (x - c) is free when every prescribed entry
// (point p, component k) sees u_k(p) = 0. Each of the six coordinate modes
// (translations, rotations about axes through the centre c) is tested on its
// own, and the null space of the 6 x 6 Gram matrix of the constraints finds
// the combinations that no coordinate mode shows: a body held along one edge
// still turns about that edge (a hinge), held at one point about any axis
// through it.

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace perideal
{
  /// The value of coordinate mode @p m (0-2 translations in x, y, z; 3-5
  /// rotations about x, y, z) in component @p c at r = x - centre.
  inline double
  rigid_mode_value(const unsigned int m, const unsigned int c, const double x, const double y, const double z)
  {
    if (m < 3)
      return m == c ? 1.0 : 0.0;
    const double r[3][3] = {{0, -z, y}, {z, 0, -x}, {-y, x, 0}};
    return r[m - 3][c];
  }

  /// Collective: the names of the rigid motions that @p prescribed (this
  /// rank's entries, by position and component) leaves free, about
  /// @p centre, for a body of half-size @p extent; empty if none.
  /// E.g. "translation in y", "rotation about the axis through (0.5, 0.125,
  /// 0.125) along (1, 0, 0)".
  /// With @p modes: each named motion's coefficients over the six
  /// coordinate modes, rotations divided by @p extent (u = sum_m c_m
  /// rigid_mode_value(m, ...) / (m < 3 ? 1 : extent)), unit length, in the
  /// order of the names.
  std::vector<std::string>
  free_rigid_modes(const std::vector<std::pair<dealii::Point<3>, unsigned int>> &prescribed,
                   const std::array<double, 3>                                  &centre,
                   const double                                                  extent,
                   const MPI_Comm                                                comm,
                   std::vector<std::array<double, 6>>                           *modes = nullptr);
} // namespace perideal
