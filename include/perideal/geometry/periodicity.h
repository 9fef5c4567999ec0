#pragma once
// Periodic directions of a scene (Discretization/Periodic directions).
//
// A periodic direction identifies the two opposite faces of the mesh's
// bounding box: a point near one face bonds with the points near the other.
// No image points are stored. A bond is an ordinary bond i -> j of the
// family, and every loop that needs its reference vector takes the minimum
// image of X_j - X_i (wrap()). The horizon must be below half of every period
// (checked at set-up), so at most one period is ever removed, and a bond's
// deformed vector is wrap(X_j - X_i) + u_j - u_i: the displacement field is
// periodic, and an affine (macroscopic) strain is not representable.

#include <array>
#include <cmath>

namespace perideal
{
  struct Periodicity
  {
    std::array<double, 3> length{{0, 0, 0}};  // the period; 0: not periodic
    std::array<double, 3> inverse{{0, 0, 0}}; // 1 / length; 0: not periodic
    std::array<double, 3> lower{{0, 0, 0}}, upper{{0, 0, 0}}; // the box, in periodic directions

    bool
    any() const
    {
      return length[0] > 0 || length[1] > 0 || length[2] > 0;
    }

    void
    set(const unsigned int d, const double low, const double high)
    {
      lower[d]   = low;
      upper[d]   = high;
      length[d]  = high - low;
      inverse[d] = 1 / length[d];
    }

    /// Minimum image of the bond vector (e_x, e_y, e_z) = X_j - X_i, in place:
    /// e - L rint(e / L) (|e| < L, and a bond is shorter than L/2). Exactly
    /// antisymmetric in floating point (rint and the rounding of e - L n are
    /// odd), so both owners of a bond see the same length. Vectorizes (one
    /// multiply, round and fused multiply-subtract per component).
    double
    wrapped(const double e, const unsigned int d) const
    {
      return e - length[d] * std::rint(e * inverse[d]);
    }

    void
    wrap(double &ex, double &ey, double &ez) const
    {
      ex = wrapped(ex, 0);
      ey = wrapped(ey, 1);
      ez = wrapped(ez, 2);
    }
  };
} // namespace perideal
