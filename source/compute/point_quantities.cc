// The built-in quantities of a compute, registered as
// Registry<PointQuantity> (point_quantity.h). The vector ones take one
// component each: "Displacement x" is Displacement<0>.
#include <perideal/compute/point_quantity.h>
#include <perideal/continuum/continuum_field.h>
#include <perideal/model/force_model.h>

namespace perideal
{
  using namespace dealii;

  /// The FE DoF of component c at node k holds the component's value.
  template <unsigned int c>
  class ComponentQuantity : public PointQuantity
  {
  public:
    bool
    at_node(const unsigned int component) const override
    {
      return component == c;
    }
  };

  template <unsigned int c>
  class Displacement : public ComponentQuantity<c>
  {
  public:
    double
    value(const ComputeData &data, const unsigned int i) const override
    {
      return data.state.displacement.local_element(dim * i + c);
    }
    double
    node_value(const ComputeData &data, const unsigned int k) const override
    {
      return data.continuum->U.local_element(data.continuum->nodes[k].local);
    }
  };

  template <unsigned int c>
  class Force : public ComponentQuantity<c>
  {
  public:
    double
    value(const ComputeData &data, const unsigned int i) const override
    {
      return data.cloud.volume[i] * data.state.force.local_element(dim * i + c);
    }
    double
    node_value(const ComputeData &data, const unsigned int k) const override
    {
      return data.continuum->F.local_element(data.continuum->nodes[k].local);
    }
  };

  template <unsigned int c>
  class Position : public ComponentQuantity<c>
  {
  public:
    double
    value(const ComputeData &data, const unsigned int i) const override
    {
      return data.cloud.X[dim * i + c];
    }
    double
    node_value(const ComputeData &data, const unsigned int k) const override
    {
      return data.continuum->nodes[k].x[data.continuum->nodes[k].component];
    }
  };

  class Damage : public PointQuantity
  {
  public:
    double
    value(const ComputeData &data, const unsigned int i) const override
    {
      return data.model.point_damage(i);
    }
  };

  class BondStretch : public PointQuantity
  {
  public:
    double
    value(const ComputeData &data, const unsigned int i) const override
    {
      return data.model.point_stretch(i);
    }
  };

  class KineticEnergy : public PointQuantity
  {
  public:
    double
    value(const ComputeData &data, const unsigned int i) const override
    {
      const double *v = data.state.velocity.begin() + dim * i;
      return 0.5 * data.state.mass_density[i] * data.cloud.volume[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    }
    bool
    at_node(const unsigned int) const override
    {
      return true;
    }
    double
    node_value(const ComputeData &data, const unsigned int k) const override
    {
      const unsigned int local = data.continuum->nodes[k].local;
      const double       vk    = data.continuum->V.local_element(local);
      return 0.5 * data.continuum->mass.local_element(local) * vk * vk;
    }
  };

  using DisplacementX = Displacement<0>;
  using DisplacementY = Displacement<1>;
  using DisplacementZ = Displacement<2>;
  using ForceX        = Force<0>;
  using ForceY        = Force<1>;
  using ForceZ        = Force<2>;
  using PositionX     = Position<0>;
  using PositionY     = Position<1>;
  using PositionZ     = Position<2>;

  const char *const doc_displacement = "of a point.";
  const char *const doc_force = "the force on a point, V f (force density times volume), internal plus body force; its "
                            "sum over a region of prescribed points is minus the reaction there.";
  const char *const doc_position = "the reference position of a point (with Mean: where a region's mean displacement "
                               "is taken, e.g. for the length of a virtual strain gauge).";
  PERIDEAL_REGISTER(PointQuantity, DisplacementX, "Displacement x", doc_displacement)
  PERIDEAL_REGISTER(PointQuantity, DisplacementY, "Displacement y", doc_displacement)
  PERIDEAL_REGISTER(PointQuantity, DisplacementZ, "Displacement z", doc_displacement)
  PERIDEAL_REGISTER(PointQuantity, ForceX, "Force x", doc_force)
  PERIDEAL_REGISTER(PointQuantity, ForceY, "Force y", doc_force)
  PERIDEAL_REGISTER(PointQuantity, ForceZ, "Force z", doc_force)
  PERIDEAL_REGISTER(PointQuantity, PositionX, "Position x", doc_position)
  PERIDEAL_REGISTER(PointQuantity, PositionY, "Position y", doc_position)
  PERIDEAL_REGISTER(PointQuantity, PositionZ, "Position z", doc_position)
  PERIDEAL_REGISTER(PointQuantity, Damage, "Damage", "point damage.")
  PERIDEAL_REGISTER(PointQuantity, BondStretch, "Bond stretch",
                    "the largest stretch (|y| - |xi|)/|xi| of a point's intact bonds (with Maximum: how close "
                    "the region is to a critical stretch).")
  PERIDEAL_REGISTER(PointQuantity, KineticEnergy, "Kinetic energy", "1/2 rho V |v|^2 of a point.")
} // namespace perideal
