#pragma once
// The boundary and initial conditions of a run as sets of degrees of
// freedom (MechanicalState's numbering, points' and FE DoFs alike) or
// boundary faces; the prescribed DoFs (a later condition on the same DoF
// wins), the loads (body force density at point entries, nodal loads at FE
// DoFs) and the force the supports put on the body.

#include <perideal/conditions/boundary_conditions.h>
#include <perideal/discretization/discretization.h>
#include <perideal/model/state.h>

#include <cstdint>
#include <vector>

namespace perideal
{
  class ContinuumField;
  class Coupling;

  class ConditionSet
  {
  public:
    ConditionSet(std::vector<BoundaryCondition> &conditions, const Discretization &discretization,
                 MechanicalState &state, RunRecord &record, const MPI_Comm comm);

    /// The points, nodes and faces of every condition. Collective.
    void
    setup(Coupling *coupling);
    /// The prescribed entries (a warning where two conditions set the same
    /// one) and the loads. Collective.
    void
    setup_constraints();

    /// Initial displacements and velocities (and where prescribed
    /// velocities start from), the loads at @p time. Collective.
    void
    apply_initial_conditions(const double time);
    /// body_force (point entries) and the FE load (body forces at nodes,
    /// tractions on faces) of the load conditions at @p time (if any).
    void
    evaluate_loads(const double time);
    /// The prescribed entries for the step of length @p step_dt that ends at @p time.
    void
    apply_prescribed(const double time, const double step_dt);
    /// 1 + the index of the first condition whose value is not finite at one
    /// of its (owned) points at @p time; 0 if none.
    unsigned int
    first_nonfinite_condition(const double time) const;
    /// Collective: stops naming the condition and point if any rank has @p bad_local > 0.
    void
    check_condition_values(const unsigned int bad_local, const double time) const;
    /// The load on DoF @p k: body force density at a point entry, nodal
    /// load at an FE DoF (0 where none).
    double
    load(const unsigned int k) const
    {
      if (state.is_fe(k))
        return fe_load ? fe_load[state.fe_local(k)] : 0.0;
      return body_force.empty() ? 0.0 : body_force[k];
    }
    bool
    has_loads() const
    {
      return !body_force.empty() || fe_load != nullptr;
    }

    struct Constraint
    {
      unsigned int dof, condition;
    };
    /// The force the support of prescribed DoF @p c puts on the body:
    /// m a - w f (without acceleration, quasistatic: -w f).
    double
    support_force(const Constraint &c) const;

    /// After cells converted (the constraints numbered again): each
    /// constraint's force and displacement from the carried state.
    void
    take_constraint_state();
    /// After apply_prescribed() of a step it had applied before (a load
    /// step solved again after a conversion): each prescribed velocity's
    /// displacement back to @p integrated, what it had integrated over the
    /// step (constraint_displacement before), so that the step counts once.
    void
    keep_integrated(const std::vector<double> &integrated);

    /// The constraints' own state (checkpoint.h): the force of the last
    /// step and a prescribed velocity's displacement.
    void
    save(CheckpointWriter &out) const;
    void
    load(CheckpointReader &in);

    std::vector<BoundaryCondition> &conditions;
    std::vector<Constraint>         constraints;             // the prescribed DoFs, by number
    std::vector<std::uint8_t>       prescribed;              // per DoF: 1 if a constraint holds it
    std::vector<double>             constraint_force;        // f there, previous step (Verlet)
    std::vector<double>             constraint_displacement; // per constraint: its own u (prescribed velocity)
    std::vector<double>             body_force; // per point entry; empty if none
    bool                            loads_depend_on_time = false;
    unsigned int                    bad_condition = 0; // 1 + index of a condition that gave a non-finite value

  private:
    /// A Traction's owned boundary faces in its Region (or of its Boundary
    /// id): of FE cells, and of PD cells with the point each loads.
    void
    find_traction_faces(BoundaryCondition &bc) const;

    const Discretization &discretization;
    const PointCloud     &cloud;
    MechanicalState      &state;
    RunRecord            &record;
    MPI_Comm              comm;
    ContinuumField       *continuum = nullptr;
    const std::vector<double> *node_density = nullptr;
    const double              *fe_load      = nullptr; // the continuum's nodal load, if any
    // The points' entries when setup() last ran: a condition's dofs below
    // it are its points then (dim i + component), the rest its FE nodes.
    std::size_t point_entries_then = 0;
  };
} // namespace perideal
