#pragma once
// The force model: per block a Material and an optional DamageModel over the
// block's points, the per-point fields they ask for (made ghosted where they
// say so), the bond damage, and the one evaluation every integrator, tangent
// and report uses: damage, material stages, ghost exchange, forces, the load
// conditions' body force and the coupling's transfer to the FE nodes.

#include <perideal/base/expression.h>
#include <perideal/discretization/discretization.h>
#include <perideal/damage/damage_model.h>
#include <perideal/material/material.h>
#include <perideal/model/block.h>
#include <perideal/model/rigid_bodies.h>
#include <perideal/model/state.h>

#include <deal.II/base/timer.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace perideal
{
  class Contact;
  class Coupling;

  /// The fields every registered material and damage model offers as output
  /// (those with an output_name), in registry order, each output name once.
  /// A run may write those of its blocks' models (0 in the blocks of others).
  std::vector<PointField>
  model_output_fields();
  /// The registered materials and damage models that offer the output
  /// variable @p output_name, as "A or B" (for error messages).
  std::string
  models_with_output(const std::string &output_name);

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
    /// The contact forces compute_forces() adds (null: no contact).
    void
    attach_contact(Contact *contact_)
    {
      contact = contact_;
    }
    /// The contact (null without).
    const Contact *
    contact_forces() const
    {
      return contact;
    }

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
    /// With keep_point_steps(), a rebuild that keeps families
    /// (Discretization::previous_families) carries over the step of each
    /// point whose family and whose neighbors' families it kept, and
    /// computes only the others'.
    double
    stable_time_step();
    /// Keeps each point's stable step for the rebuilds of a run with
    /// Adaptivity (a scene without conversions keeps none). Call before setup().
    void
    keep_point_steps()
    {
      keeping_steps = true;
    }
    /// The points whose step the last stable_time_step() carried over and
    /// those whose step it computed (every rank's; with keep_point_steps()).
    std::pair<double, double>
    carried_steps() const
    {
      return {n_carried_steps, n_point_steps};
    }

    /// The points this rank has neglected so far (Critical damage to
    /// neglect material point): their bonds all broken.
    std::size_t
    neglected_points() const
    {
      return n_neglected;
    }

    /// 1 - (intact neighbor volume)/(neighbor volume) of owned point @p i.
    double
    point_damage(const unsigned int i) const;
    /// The largest stretch of the intact bonds of owned point @p i (ghosted displacement).
    double
    point_stretch(const unsigned int i) const;
    /// The largest speed of a point with mass and an intact bond. Collective.
    double
    fastest_bonded_speed() const;
    /// The bond damage at one moment (released_energy()).
    struct DamageSnapshot
    {
      std::vector<std::uint8_t> broken;
      std::vector<double>       damage; // empty without a continuous damage model
      // damage_updates when copied: the copy is current while it is unchanged.
      std::size_t updates = std::numeric_limits<std::size_t>::max();
    };
    /// Copies the bond damage of now into @p into (reusing its memory),
    /// unless this rank's damage is unchanged since @p into was taken: a
    /// solver that keeps one snapshot copies only after steps that broke
    /// bonds here.
    void
    save_damage(DamageSnapshot &into) const
    {
      if (into.updates == damage_updates)
        return;
      into.broken  = broken;
      into.damage  = damage;
      into.updates = damage_updates;
    }
    /// What a cut implicit step returns to: the bond damage and the
    /// neglected points.
    struct DamageState
    {
      DamageSnapshot bonds;
      VectorType     neglected; // only with neglect
      std::size_t    n_neglected     = 0;
      bool           neglect_current = true; // the points were checked at this damage
    };
    /// Copies the damage state of now into @p into (the bonds only if they
    /// changed since @p into was taken, as save_damage()).
    void
    save_damage_state(DamageState &into) const
    {
      save_damage(into.bonds);
      if (neglecting)
        into.neglected = neglected;
      into.n_neglected     = n_neglected;
      into.neglect_current = neglect_checked == damage_updates;
    }
    /// Returns to @p from (taken by save_damage_state()); nothing to do if no
    /// bond changed since. Collective only with neglect.
    void
    restore_damage_state(const DamageState &from);
    /// The bond damage, the neglected points and the models' committed
    /// history (checkpoint.h). load() is collective with neglect.
    void
    save(CheckpointWriter &out) const;
    void
    load(CheckpointReader &in);
    /// The strain energy that bond damage released at the current state:
    /// with the damage of @p before minus with that of now, summed over
    /// ranks (for continuous damage the energy released as d rose, to first
    /// order in its rise). Leaves the forces and energy densities of now
    /// (Material::released_energy()); @p before then holds now's damage.
    /// Collective.
    double
    released_energy(DamageSnapshot &before);
    /// Runs the damage models on the current state; returns the bonds
    /// (directed, all ranks) broken now, or whose continuous damage rose.
    std::size_t
    break_bonds();
    /// True if some block's damage model is continuous (damage is allocated).
    bool
    continuous_damage() const
    {
      return !damage.empty();
    }

    /// The time of the state the next evaluations see and the step that led
    /// to it (ModelState::time, dt). The integrators set it with the step's
    /// prescribed values (ConditionSet::apply_prescribed), before its first
    /// evaluation.
    void
    set_time(const double time_, const double dt_)
    {
      time = time_;
      dt   = dt_;
      if (temperature_function && temperature_function->depends_on_time())
        update_temperature();
      if (time_dependent_limits)
        set_stretch_limits();
    }

    /// The temperature field T(x, y, z, t) and T_ref (thermal strain,
    /// doc/thermal.md): every evaluation then passes alpha (T - T_ref) at the
    /// time of set_time() (ModelState::thermal_strain, alpha that of each
    /// point's material). Without it none is allocated. Call before setup().
    void
    set_temperature(std::unique_ptr<Expression> function, const double reference)
    {
      temperature_function  = std::move(function);
      reference_temperature = reference;
    }
    /// The temperature T of local point @p i; only with a temperature field.
    double
    temperature(const unsigned int i) const
    {
      return temperature_change.local_element(i) + reference_temperature;
    }
    bool
    has_temperature() const
    {
      return temperature_function != nullptr;
    }

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
    RigidBodies                rigid; // the rigid blocks; compute_forces() moves each as one body
    std::vector<std::uint8_t>  broken;            // per bond, only with a damage model
    // Continuous d per bond, only with a continuous damage model
    // (DamageModel::continuous()); d = 1 is also marked in broken.
    std::vector<double>        damage;
    bool                       breaking_allowed = true; // false: damage changes only in break_bonds()
    // Bonds broken, or whose continuous d rose, so far (directed, this rank):
    // a step that changes it changes the damage.
    std::size_t                damage_updates = 0;

  private:
    Discretization          &discretization;
    const PointCloud        &cloud;
    const Bonds             &bonds;
    MechanicalState         &mechanical;
    RunRecord               &record;
    MPI_Comm                 comm;
    dealii::TimerOutput     &timer;
    std::unique_ptr<FieldStore> fields;
    std::vector<bool>           continuous; // by block: its damage model is continuous
    /// @p state for block @p k's material: with the continuous damage if its
    /// damage model is continuous, and the time.
    ModelState
    block_state(const ModelState &state, const unsigned int k) const;
    /// The bond damage for DamageModel::update().
    BondDamageArrays
    arrays()
    {
      return {broken.data(), damage.data()};
    }
    bool                        has_stage_fields = false;
    bool                        unclaimed_reported = false; // warn_unclaimed_cells() said it at the set-up
    // released_energy()'s points per block and the default evaluation's
    // scratch force and energy density (kept: no allocation per step).
    std::vector<std::vector<unsigned int>> released_points;
    std::vector<double>                    released_force, released_density;
    // Per block: the critical stretch its material applies in its force loop,
    // one for all its bonds or by the far end's block; fused[b] false:
    // damage_pass() runs its own pass.
    std::vector<StretchBreaking>     fused_breaking;
    std::vector<bool>                fused;
    std::vector<std::vector<double>> limit_at; // by block fusing by the far end: the limit by point
    /// Force blending: per block, the points whose force is read, when not
    /// all of them (a continuum block's node points; its virtual points'
    /// forces go nowhere). Empty: all of the block's points.
    std::vector<std::vector<unsigned int>> read_points;
    BondStretchLimits            stretch_limits; // the critical stretch of each bond, across blocks
    bool                         time_dependent_limits = false; // some block's critical stretch depends on time
    // Critical damage to neglect material point: 1 at a point once neglected,
    // ghosted; allocated only if some block's threshold is below 1.
    VectorType  neglected;
    bool        neglecting      = false;
    std::size_t neglect_checked = 0; // damage_updates when the points were last checked
    std::size_t n_neglected     = 0;
    /// Neglects the points of this rank whose damage exceeds their block's
    /// threshold, then breaks every intact bond with a neglected end, on
    /// every rank (both halves alike). Collective.
    void
    neglect_damaged_points();
    // keep_point_steps(): the stable step per owned point (the largest
    // double where it has none), and the counts of the last evaluation.
    bool                keeping_steps = false;
    std::vector<double> point_step;
    double              n_carried_steps = 0, n_point_steps = 0;
    /// Per owned point: its index before the rebuild if its stable step is
    /// carried over (it and every neighbor kept their families), else
    /// numbers::invalid_unsigned_int. Collective when a rebuild keeps families.
    std::vector<unsigned int>
    carried_step_sources() const;
    /// Block @p b's smallest step, point by point into @p steps: carried
    /// from point_step where @p source names the point before, else from
    /// its material. Counts into @p carried and, with Adaptivity/Check
    /// kept families, the carried steps that differ from a new one into @p differ.
    double
    block_step_by_point(const ModelState &state, const Block &b, const std::vector<unsigned int> &source,
                        std::vector<double> &steps, double &carried, unsigned int &differ) const;
    /// The critical stretches of every block at the current time, into
    /// stretch_limits and the fused limits.
    void
    set_stretch_limits();
    /// setup()'s steps, in their order: each block's owned points; bonds
    /// only between blocks of one model; the bond damage arrays; damage
    /// laws that agree across blocks; the state vectors and masses; the
    /// models' fields; the materials' and damage models' set-up; the
    /// damage options (neglected points, the stretch limits).
    void
    collect_block_points();
    void
    check_models_across_blocks() const;
    void
    setup_bond_damage();
    void
    check_damage_laws_across_blocks() const;
    void
    setup_mechanical_state();
    void
    declare_model_fields();
    void
    initialize_models();
    void
    setup_damage_options();
    const std::vector<double>   *body_force = nullptr;
    Coupling                    *coupling   = nullptr;
    Contact                     *contact    = nullptr;
    double                       time = 0, dt = 0; // set_time()
    std::unique_ptr<Expression>  temperature_function; // null: no temperature field
    double                       reference_temperature = 0;
    VectorType                   temperature_change; // T - T_ref per local point, ghosted
    VectorType                   thermal_strain;     // alpha dT (ModelState::thermal_strain), ghosted
    /// dT at every owned point at the current time, then its ghosts.
    /// Collective (a non-finite value stops every rank).
    void
    update_temperature();
  };
} // namespace perideal
