// The built-in quantities of a compute, registered as
// Registry<PointQuantity> (point_quantity.h). The vector ones take one
// component each: "Displacement x" is Displacement<0>.
#include <perideal/compute/point_quantity.h>
#include <perideal/continuum/continuum_field.h>
#include <perideal/model/force_model.h>

#include <cmath>

namespace perideal
{
  using namespace dealii;

  /// The FE DoF of component c at node k holds the component's value.
  namespace
  {
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
    class Velocity : public ComponentQuantity<c>
    {
    public:
      double
      value(const ComputeData &data, const unsigned int i) const override
      {
        return data.state.velocity.local_element(dim * i + c);
      }
      double
      node_value(const ComputeData &data, const unsigned int k) const override
      {
        return data.continuum->V.local_element(data.continuum->nodes[k].local);
      }
    };

    template <unsigned int c>
    class Momentum : public ComponentQuantity<c>
    {
    public:
      double
      value(const ComputeData &data, const unsigned int i) const override
      {
        return data.state.mass_density[i] * data.cloud.volume[i] * data.state.velocity.local_element(dim * i + c);
      }
      double
      node_value(const ComputeData &data, const unsigned int k) const override
      {
        const unsigned int local = data.continuum->nodes[k].local;
        return data.continuum->mass.local_element(local) * data.continuum->V.local_element(local);
      }
    };

    /// Component c of m (y x v) about the origin, y = X + u the current position.
    template <unsigned int c>
    class AngularMomentum : public PointQuantity
    {
    public:
      double
      value(const ComputeData &data, const unsigned int i) const override
      {
        constexpr unsigned int a = (c + 1) % 3, b = (c + 2) % 3;
        const double          *u = data.state.displacement.begin() + dim * i;
        const double          *v = data.state.velocity.begin() + dim * i;
        const double          *X = data.cloud.X.data() + dim * i;
        return data.state.mass_density[i] * data.cloud.volume[i] *
               ((X[a] + u[a]) * v[b] - (X[b] + u[b]) * v[a]);
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

    /// How far a crack has run past an origin along a direction: at a point
    /// whose damage has reached the threshold, (X - origin) . direction; 0
    /// elsewhere, so that Maximum over a region is 0 until the crack enters it.
    /// Damage never heals, so with reference positions the tip never retreats.
    class CrackTip : public PointQuantity
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Crack direction", "1,0,0", Patterns::List(Patterns::Double(), 3, 3),
                          "Variable = Crack tip only: the direction the crack runs in (normalised).");
        prm.declare_entry("Crack origin", "0,0,0", Patterns::List(Patterns::Double(), 3, 3),
                          "Variable = Crack tip only: where the crack length is measured from, e.g. the notch "
                          "tip.");
        prm.declare_entry("Crack damage threshold", "0.3", Patterns::Double(),
                          "Variable = Crack tip only: a point is on the crack once its damage reaches this, in "
                          "(0, 1]. The points along a crack's faces lose a third to a half of their bonds; 0.3 "
                          "marks the tip where they have lost most of that.");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path) override
      {
        direction = get_point(prm, "Crack direction");
        origin    = get_point(prm, "Crack origin");
        threshold = prm.get_double("Crack damage threshold");
        AssertThrow(direction.norm() > 0 && std::isfinite(direction.norm()),
                    ExcMessage(path + "/Crack direction: give a direction, e.g. 1,0,0; got " +
                               prm.get("Crack direction")));
        direction /= direction.norm();
        AssertThrow(threshold > 0 && threshold <= 1,
                    ExcMessage(path + "/Crack damage threshold must be in (0, 1], got " +
                               prm.get("Crack damage threshold")));
        AssertThrow(prm.get("Operation") == "Maximum",
                    ExcMessage(path + "/Operation: Variable = Crack tip is 0 at the points the crack has not "
                               "reached, so only Maximum gives the crack's length (got " + prm.get("Operation") +
                               ")"));
      }

      double
      value(const ComputeData &data, const unsigned int i) const override
      {
        if (data.model.point_damage(i) < threshold)
          return 0;
        double s = 0;
        for (unsigned int d = 0; d < dim; ++d)
          s += (data.cloud.X[dim * i + d] - origin[d]) * direction[d];
        return s;
      }

    private:
      Point<dim> direction, origin;
      double     threshold = 0.3;
    };

    /// The von Mises stress of a correspondence material's point (its stage
    /// field); 0 at the points of materials without a stress tensor.
    class VonMisesStressQuantity : public PointQuantity
    {
    public:
      double
      value(const ComputeData &data, const unsigned int i) const override
      {
        const VectorType *values = data.model.field("corr_von_mises");
        return values ? values->local_element(i) : 0.0;
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
    using VelocityX     = Velocity<0>;
    using VelocityY     = Velocity<1>;
    using VelocityZ     = Velocity<2>;
    using MomentumX     = Momentum<0>;
    using MomentumY     = Momentum<1>;
    using MomentumZ     = Momentum<2>;
    using AngularMomentumX = AngularMomentum<0>;
    using AngularMomentumY = AngularMomentum<1>;
    using AngularMomentumZ = AngularMomentum<2>;
    using PositionX     = Position<0>;
    using PositionY     = Position<1>;
    using PositionZ     = Position<2>;

    const char *const doc_displacement = "of a point.";
    const char *const doc_force = "the force on a point, V f (force density times volume), internal plus body force; its "
                              "sum over a region of prescribed points is minus the reaction there.";
    const char *const doc_momentum = "rho V v of a point (with Sum over All: the linear momentum of the body; "
                                     "FE nodes: lumped mass times velocity).";
    const char *const doc_angular = "rho V (y x v) of a point about the origin, y its current position (with Sum "
                                    "over All: the angular momentum of the PD points).";
    const char *const doc_position = "the reference position of a point (with Mean: where a region's mean displacement "
                                 "is taken, e.g. for the length of a virtual strain gauge).";
  } // namespace

  PERIDEAL_REGISTER(PointQuantity, DisplacementX, "Displacement x", doc_displacement)
  PERIDEAL_REGISTER(PointQuantity, DisplacementY, "Displacement y", doc_displacement)
  PERIDEAL_REGISTER(PointQuantity, DisplacementZ, "Displacement z", doc_displacement)
  PERIDEAL_REGISTER(PointQuantity, ForceX, "Force x", doc_force)
  PERIDEAL_REGISTER(PointQuantity, ForceY, "Force y", doc_force)
  PERIDEAL_REGISTER(PointQuantity, ForceZ, "Force z", doc_force)
  PERIDEAL_REGISTER(PointQuantity, VelocityX, "Velocity x", "of a point.")
  PERIDEAL_REGISTER(PointQuantity, VelocityY, "Velocity y", "of a point.")
  PERIDEAL_REGISTER(PointQuantity, VelocityZ, "Velocity z", "of a point.")
  PERIDEAL_REGISTER(PointQuantity, MomentumX, "Momentum x", doc_momentum)
  PERIDEAL_REGISTER(PointQuantity, MomentumY, "Momentum y", doc_momentum)
  PERIDEAL_REGISTER(PointQuantity, MomentumZ, "Momentum z", doc_momentum)
  PERIDEAL_REGISTER(PointQuantity, AngularMomentumX, "Angular momentum x", doc_angular)
  PERIDEAL_REGISTER(PointQuantity, AngularMomentumY, "Angular momentum y", doc_angular)
  PERIDEAL_REGISTER(PointQuantity, AngularMomentumZ, "Angular momentum z", doc_angular)
  PERIDEAL_REGISTER(PointQuantity, PositionX, "Position x", doc_position)
  PERIDEAL_REGISTER(PointQuantity, PositionY, "Position y", doc_position)
  PERIDEAL_REGISTER(PointQuantity, PositionZ, "Position z", doc_position)
  PERIDEAL_REGISTER(PointQuantity, Damage, "Damage", "point damage.")
  PERIDEAL_REGISTER(PointQuantity, CrackTip, "Crack tip",
                    "with Operation = Maximum, how far the crack has run from Crack origin along Crack "
                    "direction: the farthest point (reference position) whose damage has reached Crack damage "
                    "threshold, 0 until one has; with Rate, the crack speed (doc/models.md, Crack tip).")
  PERIDEAL_REGISTER(PointQuantity, VonMisesStressQuantity, "Von Mises stress",
                    "of a point of a correspondence material, sqrt(3 J2) of its Cauchy stress (0 at the points of "
                    "other materials; a scene without such a material is refused); with Maximum: where a Von "
                    "Mises stress damage model stands.")
  PERIDEAL_REGISTER(PointQuantity, BondStretch, "Bond stretch",
                    "the largest stretch (|y| - |xi|)/|xi| of a point's intact bonds (with Maximum: how close "
                    "the region is to a critical stretch).")
  PERIDEAL_REGISTER(PointQuantity, KineticEnergy, "Kinetic energy", "1/2 rho V |v|^2 of a point.")
} // namespace perideal
