#pragma once
// A bond filter (Peridigm's "Bond Filters", type Rectangular_Plane): a
// rectangle in the reference configuration that no bond may cross. Bonds
// whose segment X_i -> X_j meets it are left out of the families at set-up,
// so a pre-crack or notch of zero width cuts the material exactly, which a
// slot of removed cells narrower than a horizon does not (bonds reach across
// it). The rectangle: a corner, the unit vector along its bottom edge, its
// normal, the bottom edge's length and the side's. The side runs along
// bottom x normal, as in Peridigm (PeriDeal before 2026-12 took
// normal x bottom: such a deck keeps its rectangle with Normal negated).

#include <perideal/base/input.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <string>

namespace perideal
{
  class BondFilter
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm);
    /// The rectangle's keys without Type (shared with InitialDamage).
    static void
    declare_plane_parameters(ParameterHandler &prm);
    /// @p path names the subsection in error messages.
    void
    parse_parameters(ParameterHandler &prm, const std::string &path);

    /// Whether the segment @p a -> @p b meets the rectangle (end points on
    /// it included; a segment lying in its plane does not cut).
    bool
    cuts(const dealii::Point<dim> &a, const dealii::Point<dim> &b) const;
    /// The distance from @p x to the rectangle: no segment from @p x
    /// shorter than it can cut.
    double
    distance(const dealii::Point<dim> &x) const;

    std::string name;

  private:
    dealii::Point<dim>     corner;
    dealii::Tensor<1, dim> normal, bottom, side; // unit vectors
    double                 bottom_length = 0, side_length = 0;
  };
} // namespace perideal
