#pragma once
// The force model: per block a Material and an optional DamageModel over the
// block's points, the per-point fields they ask for (made ghosted where they
// say so), the bond damage, and the one evaluation every integrator, tangent
// and report uses: damage, material stages, ghost exchange, forces, the load
// conditions' body force and the coupling's transfer to the FE nodes.

#include <perideal/discretization/discretization.h>
#include <perideal/damage/damage_model.h>
#include <perideal/material/material.h>
#include <perideal/model/block.h>
#include <perideal/model/state.h>

#include <deal.II/base/timer.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace perideal
{
  class Coupling;

  /// The scalar fields every registered material and damage model offers as
  /// output: (Output/Variables name, field name), in registry order, each
  /// output name once. Written for every run (0 where a block's model does
  /// not have it).
  std::vector<std::pair<std::string, std::string>>
  model_output_fields();

  class ForceModel
  {
  public:
    ForceModel(Discretization &discretization, MechanicalState &state, RunRecord &record, const MPI_Comm comm,
               dealii::TimerOutput &timer);

    /// The blocks' points, the state vectors, the bond damage and the
    /// materials' and damage models' set-up. Collective.
    void
    setup();

    /// What compute_forces() adds besides the materials: the body force
    /// density per owned PD entry (may be empty) and the coupling (may be null).
    void
    attach(const std::vector<double> &body_force, Coupling *coupling);

    /// The force density at every point (and, with continuum blocks, the FE
    /// nodal forces) of the current displacement, whose ghosts must be
    /// current; the strain energy density too if @p with_energy.
    void
    compute_forces(const bool with_energy);

    /// Adds every block's analytic tangent (Material::add_tangent) at the
    /// current state to @p rows; false (and stops) at the first block whose
    /// material has none.
    bool
    add_tangent(TangentRows &rows) const;

    /// The smallest stable explicit step over all points (and FE cells). Collective.
    double
    stable_time_step();

    /// 1 - (intact neighbor volume)/(neighbor volume) of owned point @p i.
    double
    point_damage(const unsigned int i) const;
    /// The largest stretch of the intact bonds of owned point @p i (ghosted displacement).
    double
    point_stretch(const unsigned int i) const;
    /// The largest speed of a point with mass and an intact bond. Collective.
    double
    fastest_bonded_speed() const;
    /// The strain energy that bond breaking released at the current state:
    /// with the bonds of @p mask_before (the broken flags before the breaks)
    /// minus with those of now, summed over ranks. Leaves the forces and
    /// energy densities of now. Collective.
    double
    released_energy(std::vector<std::uint8_t> &mask_before);
    /// Runs the damage models on the current state; returns the bonds
    /// (directed) broken now, all ranks.
    std::size_t
    break_bonds();

    /// The step is accepted: every model's history becomes the state the
    /// next step starts from (FieldStore::commit()). The integrators call
    /// it exactly once per accepted step, never inside a Newton iteration.
    void
    commit_step()
    {
      fields->commit();
    }
    /// A per-point field a model declared, or nullptr.
    const VectorType *
    field(const std::string &name) const
    {
      return fields && fields->has(name) ? &fields->get(name) : nullptr;
    }
    /// The whole store (a model's history, for tests and output).
    FieldStore &
    field_store()
    {
      return *fields;
    }
    std::size_t
    field_memory() const
    {
      return fields->memory_consumption();
    }

    std::vector<Block>        &blocks;
    std::vector<std::uint8_t>  broken;            // per bond, only with a damage model
    bool                       breaking_allowed = true; // false: bonds break only in break_bonds()
    std::size_t                broken_bond_count = 0;   // directed entries, this rank

  private:
    Discretization          &discretization;
    const PointCloud        &cloud;
    const Bonds             &bonds;
    MechanicalState         &mechanical;
    RunRecord               &record;
    MPI_Comm                 comm;
    dealii::TimerOutput     &timer;
    std::unique_ptr<FieldStore> fields;
    bool                        has_stage_fields = false;
    // Per block: the critical stretch its material applies in its force loop
    // (squared_limit 0: not fused, damage_pass() runs its own pass).
    std::vector<StretchBreaking> fused_breaking;
    BondStretchLimits            stretch_limits; // the critical stretch of each bond, across blocks
    const std::vector<double>   *body_force = nullptr;
    Coupling                    *coupling   = nullptr;
  };
} // namespace perideal
