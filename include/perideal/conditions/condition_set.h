#pragma once
// The boundary and initial conditions of a run as sets of degrees of
// freedom: per condition its PD points, FE nodes or boundary faces; the
// prescribed entries (a later condition on the same entry wins), the loads
// (body force density at PD points, nodal loads of FE nodes) and the force
// the supports put on the body.

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
    /// body_force (PD points) and the FE load (body forces at nodes,
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
    /// Per owned FE DoF: 1 if a prescribed condition holds it.
    std::vector<std::uint8_t>
    fe_prescribed_flags() const;

    struct Constraint
    {
      unsigned int point, component, condition;
    };
    struct NodeConstraint
    {
      unsigned int node, condition; // index into the continuum's nodes
    };
    /// The force the support of prescribed entry @p c puts on the body:
    /// m a - V f (quasistatic, no acceleration: -V f).
    double
    support_force(const Constraint &c) const;
    /// The same at an FE node: M a - F.
    double
    node_support_force(const NodeConstraint &c) const;

    std::vector<BoundaryCondition> &conditions;
    std::vector<Constraint>         constraints;               // prescribed (point, component)
    std::vector<double>             constraint_force;          // internal force there, previous step
    std::vector<double>             constraint_displacement;   // per constraint: its own u (prescribed velocity)
    std::vector<NodeConstraint>     node_constraints;
    std::vector<double>             node_constraint_force;
    std::vector<double>             node_constraint_displacement;
    std::vector<double>             body_force; // per owned point and component; empty if none
    bool                            loads_depend_on_time = false;
    unsigned int                    bad_condition = 0; // 1 + index of a condition that gave a non-finite value

  private:
    const Discretization &discretization;
    const PointCloud     &cloud;
    MechanicalState      &state;
    RunRecord            &record;
    MPI_Comm              comm;
    ContinuumField       *continuum = nullptr;
    const std::vector<double> *node_density = nullptr;
    bool                       has_continuum = false;
  };
} // namespace perideal
