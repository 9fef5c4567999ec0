#include <perideal/neighborhood/bond_filter.h>

#include <deal.II/base/utilities.h>

#include <cmath>

namespace perideal
{
  using namespace dealii;

  void
  BondFilter::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Type", "Rectangular plane", Patterns::Selection("Rectangular plane"),
                      "Rectangular plane: no bond crosses the rectangle (Peridigm's Rectangular_Plane).");
    declare_plane_parameters(prm);
  }

  void
  BondFilter::declare_plane_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Lower left corner", "0,0,0", Patterns::List(Patterns::Double(), 3, 3),
                      "x,y,z of the rectangle's corner.");
    prm.declare_entry("Bottom unit vector", "1,0,0", Patterns::List(Patterns::Double(), 3, 3),
                      "Direction of the bottom edge from the corner (normalised).");
    prm.declare_entry("Normal", "0,1,0", Patterns::List(Patterns::Double(), 3, 3),
                      "Normal of the rectangle (normalised; must be perpendicular to the bottom edge). "
                      "The side edge runs along Bottom unit vector x Normal, as in Peridigm.");
    prm.declare_entry("Bottom length", "0", Patterns::Double(0), "Length of the bottom edge.");
    prm.declare_entry("Side length", "0", Patterns::Double(0), "Length of the side edge.");
  }

  void
  BondFilter::parse_parameters(ParameterHandler &prm, const std::string &path)
  {
    corner = get_point(prm, "Lower left corner");
    bottom = get_point(prm, "Bottom unit vector");
    normal = get_point(prm, "Normal");
    AssertThrow(bottom.norm() > 0 && normal.norm() > 0,
                ExcMessage(path + ": Bottom unit vector and Normal must not be zero"));
    // A norm that overflows (components near 1e155 or more) would scale the
    // vector to zero: a filter that silently cuts nothing.
    AssertThrow(std::isfinite(bottom.norm()) && std::isfinite(normal.norm()),
                ExcMessage(path + ": the length of " +
                           (std::isfinite(bottom.norm()) ? "Normal" : "Bottom unit vector") +
                           " overflows a double (it is normalised): give a direction of moderate length, "
                           "e.g. 0,1,0"));
    bottom /= bottom.norm();
    normal /= normal.norm();
    AssertThrow(std::abs(bottom * normal) < 1e-6,
                ExcMessage(path + ": Normal must be perpendicular to Bottom unit vector"));
    side          = cross_product_3d(bottom, normal); // Peridigm's orientation (BondFilter.cxx: ua = ub x n)
    bottom_length = prm.get_double("Bottom length");
    side_length   = prm.get_double("Side length");
    AssertThrow(bottom_length > 0 && side_length > 0,
                ExcMessage(path + ": Bottom length and Side length must be positive"));
  }

  bool
  BondFilter::cuts(const Point<dim> &a, const Point<dim> &b) const
  {
    const double sa = normal * (a - corner), sb = normal * (b - corner);
    if ((sa > 0 && sb > 0) || (sa < 0 && sb < 0) || sa == sb)
      return false;
    const Point<dim> q = a + (sa / (sa - sb)) * (b - a);
    const double     u = bottom * (q - corner), v = side * (q - corner);
    return u >= 0 && u <= bottom_length && v >= 0 && v <= side_length;
  }

  double
  BondFilter::distance(const Point<dim> &x) const
  {
    const Tensor<1, dim> d       = x - corner;
    const auto           outside = [](const double t, const double length) {
      return t < 0 ? -t : t > length ? t - length : 0.0;
    };
    const double u = outside(bottom * d, bottom_length), v = outside(side * d, side_length), w = normal * d;
    return std::sqrt(u * u + v * v + w * w);
  }
} // namespace perideal
