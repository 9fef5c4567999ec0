#pragma once
// The trilinear map of a hexahedron given by its 8 vertices in deal.II's
// lexicographic order (vertex k at the reference corner (k & 1, (k >> 1) & 1,
// k >> 2)): its Jacobian and its volume, computed from the vertices relative
// to the first, so that a cell far from the origin compared with its size
// keeps the digits of its edges (deal.II's measure() multiplies absolute
// coordinates: a cell of size 1e-6 at 0.5 loses all of them).

#include <perideal/base/input.h>

#include <deal.II/base/point.h>

#include <array>

namespace perideal
{
  /// The Jacobian determinant at the reference point @p t in [0, 1]^3 (a
  /// corner when every t[d] is 0 or 1).
  double
  hex_jacobian(const std::array<dealii::Point<dim>, 8> &v, const std::array<double, 3> &t);

  /// The Jacobian at the 8 corners and at the 8 Gauss points, the check of a
  /// cell read from a mesh file: valid (one_sign) if the 16 values have one
  /// sign beyond 1e-12 of the bounding box's diagonal cubed (negative: a cell
  /// numbered left-handed, which deal.II turns).
  struct HexJacobians
  {
    std::array<double, 8> corner{}; // at vertex k
    double                volume   = 0; // signed: the Gauss points' mean
    bool                  one_sign = false;
  };
  HexJacobians
  hex_jacobians(const std::array<dealii::Point<dim>, 8> &v);

  /// The volume: the Jacobian integrated by the 2-point Gauss rule in each
  /// direction, exact for the trilinear map (its Jacobian is quadratic in each
  /// reference coordinate).
  double
  hex_volume(const std::array<dealii::Point<dim>, 8> &v);

  /// The volume-weighted centroid of the trilinear map (integrated exactly by
  /// the 2-point Gauss rule in each direction), which Peridigm takes as an
  /// Exodus hexahedron's point; false, @p centroid untouched, if the map is
  /// affine (a parallelepiped: the Jacobian constant to 1e-12), whose
  /// centroid is the vertices' mean.
  bool
  hex_centroid(const std::array<dealii::Point<dim>, 8> &v, dealii::Point<dim> &centroid);

  /// The centroid of a deal.II hexahedral cell: hex_centroid(), or the mean
  /// of the vertices (cell->center(), to the bit) of a parallelepiped.
  template <typename CellIterator>
  dealii::Point<dim>
  cell_centroid(const CellIterator &cell)
  {
    std::array<dealii::Point<dim>, 8> v;
    for (unsigned int k = 0; k < 8; ++k)
      v[k] = cell->vertex(k);
    dealii::Point<dim> centroid;
    return hex_centroid(v, centroid) ? centroid : cell->center();
  }

  /// hex_volume() of a deal.II hexahedral cell.
  template <typename CellIterator>
  double
  cell_volume(const CellIterator &cell)
  {
    std::array<dealii::Point<dim>, 8> v;
    for (unsigned int k = 0; k < 8; ++k)
      v[k] = cell->vertex(k);
    return hex_volume(v);
  }
} // namespace perideal
