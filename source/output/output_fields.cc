// The core's fields of the field files, registered as Registry<OutputField>
// (output_field.h), and output_variables(), which adds the models' fields.
// Their position() fixes their order in Output/Variables and in the files.
#include <perideal/continuum/continuum_field.h>
#include <perideal/model/force_model.h>
#include <perideal/output/output_field.h>

#include <algorithm>

namespace perideal
{
  namespace
  {
    /// A vector: dim components per point, and a value per FE node, both
    /// read from one value per DoF of the mechanical state (state.h).
    class VectorField : public OutputField
    {
    public:
      unsigned int
      n_components() const override
      {
        return dim;
      }
      bool
      nodal() const final
      {
        return true;
      }
      double
      value(const ComputeData &data, const unsigned int i, const unsigned int c) const final
      {
        return dof_value(data, dim * i + c);
      }
      double
      node_value(const ComputeData &data, const unsigned int k) const final
      {
        return dof_value(data, data.state.point_entries() + data.continuum->nodes[k].local);
      }

    protected:
      /// The field at DoF @p k (a real point's entry or an FE DoF).
      virtual double
      dof_value(const ComputeData &data, const unsigned int k) const = 0;
    };

    class ScalarField : public OutputField
    {
    public:
      unsigned int
      n_components() const override
      {
        return 1;
      }
    };

    /// f / rho: at an FE DoF the lumped force over the lumped mass.
    double
    acceleration(const MechanicalState &state, const unsigned int k)
    {
      return state.density(k) > 0 ? state.f(k) / state.density(k) : 0.0; // real points have rho > 0
    }

    class Displacement : public VectorField
    {
    public:
      int
      position() const override
      {
        return 10;
      }
      double
      dof_value(const ComputeData &data, const unsigned int k) const override
      {
        return data.state.u(k);
      }
    };

    class Velocity : public VectorField
    {
    public:
      int
      position() const override
      {
        return 20;
      }
      double
      dof_value(const ComputeData &data, const unsigned int k) const override
      {
        return data.state.v(k);
      }
    };

    class ForceDensity : public VectorField
    {
    public:
      int
      position() const override
      {
        return 30;
      }
      /// At an FE DoF: the lumped force per volume, rho times the acceleration.
      double
      dof_value(const ComputeData &data, const unsigned int k) const override
      {
        const MechanicalState &state = data.state;
        return state.is_fe(k) ? (*data.node_density)[state.fe_node(k)] * acceleration(state, k) : state.f(k);
      }
    };

    class Acceleration : public VectorField
    {
    public:
      int
      position() const override
      {
        return 40;
      }
      double
      dof_value(const ComputeData &data, const unsigned int k) const override
      {
        return acceleration(data.state, k);
      }
    };

    class Damage : public ScalarField
    {
    public:
      int
      position() const override
      {
        return 50;
      }
      double
      value(const ComputeData &data, const unsigned int i, const unsigned int) const override
      {
        return data.model.point_damage(i);
      }
    };

    class Fragment : public ScalarField
    {
    public:
      int
      position() const override
      {
        return 55;
      }
      double
      value(const ComputeData &data, const unsigned int i, const unsigned int) const override
      {
        return data.fragment ? (*data.fragment)[i] : -1.0;
      }
    };

    /// T = dT + T_ref (Temperature/Function); the deck refuses it without one.
    class Temperature : public ScalarField
    {
    public:
      int
      position() const override
      {
        return 45;
      }
      double
      value(const ComputeData &data, const unsigned int i, const unsigned int) const override
      {
        return data.model.temperature(i);
      }
    };

    class NumberOfNeighbors : public ScalarField
    {
    public:
      int
      position() const override
      {
        return 70;
      }
      double
      value(const ComputeData &data, const unsigned int i, const unsigned int) const override
      {
        // Its family F(i) only: with blocks of different horizons i also
        // holds bonds to points whose family has i but that are beyond its
        // own horizon (Bonds::family), which Peridigm does not count.
        double n = 0;
        for (std::size_t b = data.bonds.offsets[i]; b < data.bonds.offsets[i + 1]; ++b)
          n += data.bonds.own(b);
        return n;
      }
    };

    class Block : public ScalarField
    {
    public:
      int
      position() const override
      {
        return 80;
      }
      double
      value(const ComputeData &data, const unsigned int i, const unsigned int) const override
      {
        return double(data.cloud.block[i]);
      }
      bool
      at_virtual_points() const override
      {
        return true;
      }
    };

    class Rank : public ScalarField
    {
    public:
      int
      position() const override
      {
        return 90;
      }
      double
      value(const ComputeData &data, const unsigned int, const unsigned int) const override
      {
        return data.rank;
      }
    };

    /// A model's point field (not registered: the models declare theirs),
    /// of its declared components; 0 in the blocks whose models do not have it.
    class ModelField : public OutputField
    {
    public:
      explicit ModelField(const PointField &field)
        : field(field.name)
        , components(field.components)
      {}
      unsigned int
      n_components() const override
      {
        return components;
      }
      int
      position() const override
      {
        return model_fields_position;
      }
      double
      value(const ComputeData &data, const unsigned int i, const unsigned int c) const override
      {
        const VectorType *values = data.model.field(field);
        return values ? values->local_element(components * i + c) : 0.0;
      }

    private:
      std::string  field;
      unsigned int components;
    };

    PERIDEAL_REGISTER(OutputField, Displacement, "Displacement",
                      "u of a point; on continuum cells the FE nodes' displacement.")
    PERIDEAL_REGISTER(OutputField, Velocity, "Velocity", "v of a point; on continuum cells the FE nodes' velocity.")
    PERIDEAL_REGISTER(OutputField, ForceDensity, "Force density",
                      "f of a point, internal plus body force per unit volume; on continuum cells the FE "
                      "nodes' lumped force times the density over their mass.")
    PERIDEAL_REGISTER(OutputField, Acceleration, "Acceleration",
                      "f / rho of a point; on continuum cells the FE nodes' lumped force over their mass.")
    PERIDEAL_REGISTER(OutputField, Temperature, "Temperature",
                      "T of a point, from Temperature/Function (only with a temperature field).")
    PERIDEAL_REGISTER(OutputField, Damage, "Damage",
                      "point damage, 1 - sum_j (1 - d_ij) V_j / sum_j V_j over a point's family.")
    PERIDEAL_REGISTER(OutputField, Fragment, "Fragment",
                      "the number of a point's fragment (Output/Fragments: the pieces the intact bonds hold "
                      "together, numbered from 0 in the order of their smallest point index; -1 at virtual "
                      "points of no fragment).")
    PERIDEAL_REGISTER(OutputField, NumberOfNeighbors, "Number of neighbors",
                      "the size of a point's family, the points within the horizon of its block, broken "
                      "bonds included (Peridigm's count). With blocks of different horizons a point is "
                      "also bonded to points whose family holds it but that lie beyond its own horizon: "
                      "those bonds act on it but are not counted here.")
    PERIDEAL_REGISTER(OutputField, Block, "Block",
                      "the index of a point's block in Blocks/Names (on continuum cells: of their block).")
    PERIDEAL_REGISTER(OutputField, Rank, "Rank", "the MPI rank that owns a point.")
  } // namespace

  std::vector<OutputVariable>
  output_variables(const std::vector<PointField> &model_fields)
  {
    std::vector<OutputVariable> variables;
    for (const auto &[name, entry] : Registry<OutputField>::instance().all())
      variables.push_back({name, entry.documentation, entry.create()});
    for (const auto &field : model_fields)
      variables.push_back({field.output_name,
                           "fields of the materials and damage models that declare them (0 in the blocks "
                           "of other models).",
                           std::make_unique<ModelField>(field)});
    std::stable_sort(variables.begin(), variables.end(), [](const OutputVariable &a, const OutputVariable &b) {
      return a.field->position() < b.field->position();
    });
    return variables;
  }
} // namespace perideal
