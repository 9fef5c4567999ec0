// The conditions as sets of degrees of freedom (condition_set.h).

#include <perideal/base/expression.h>
#include <perideal/base/format.h>
#include <perideal/conditions/condition_set.h>
#include <perideal/continuum/coupling.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace perideal
{
  using namespace dealii;

  ConditionSet::ConditionSet(std::vector<BoundaryCondition> &conditions, const Discretization &discretization,
                             MechanicalState &state, RunRecord &record, const MPI_Comm comm)
    : conditions(conditions)
    , discretization(discretization)
    , cloud(discretization.cloud)
    , state(state)
    , record(record)
    , comm(comm)
  {}

  void
  ConditionSet::setup(Coupling *coupling)
  {
    continuum     = coupling ? &coupling->continuum : nullptr;
    node_density  = coupling ? &coupling->node_density : nullptr;
    has_continuum = coupling != nullptr;
    // Conditions: their points, the constraints, the body force.
    for (auto &bc : conditions)
      {
        bc.faces.clear();
        if (bc.type == BoundaryCondition::Type::traction)
          {
            AssertThrow(has_continuum,
                        ExcMessage("Boundary conditions/" + bc.name + "/Type: a Traction acts on the boundary faces "
                                   "of continuum blocks, and this scene has none; load peridynamic blocks with "
                                   "a Body force"));
            bc.points.clear();
            bc.nodes.clear();
            for (const auto &cell : discretization.dof_handler.active_cell_iterators())
              if (cell->is_locally_owned() && cell->active_fe_index() > 0)
                for (const unsigned int f : cell->face_indices())
                  if (cell->face(f)->at_boundary() &&
                      (bc.boundary_id >= 0 ? cell->face(f)->boundary_id() == types::boundary_id(bc.boundary_id) :
                                             discretization.in_region(bc.region, cell->face(f)->center(), cell)))
                    bc.faces.emplace_back(cell, f);
            if (Utilities::MPI::sum(bc.faces.size(), comm) == 0)
              record.warnings.push_back("traction '" + bc.name + "' acts on no boundary face of a continuum block");
            continue;
          }
        bc.points.clear();
        for (unsigned int i = 0; i < cloud.n_owned(); ++i)
          if (!discretization.is_virtual(i) && discretization.in_region(bc.region, cloud.position(i), cloud.cell[i]))
            bc.points.push_back(i);
        bc.nodes.clear();
        if (has_continuum)
          for (unsigned int k = 0; k < continuum->nodes.size(); ++k)
            {
              const auto &node = continuum->nodes[k];
              if (node.component == bc.component && discretization.in_region(bc.region, node.x, node.cell))
                bc.nodes.push_back(k);
            }
        if (Utilities::MPI::sum(bc.points.size() + bc.nodes.size(), comm) == 0)
          record.warnings.push_back("boundary condition '" + bc.name + "' acts on no point (region '" +
                             bc.region + "' is empty)");
      }
  }

  void
  ConditionSet::setup_constraints()
  {
    discretization.check_region_expressions();
    // Two conditions of the same kind on the same component of a point: the
    // later one silently replaced the earlier there. Say so.
    for (unsigned int a = 0; a < conditions.size(); ++a)
      for (unsigned int b = a + 1; b < conditions.size(); ++b)
        {
          const auto &ca = conditions[a], &cb = conditions[b];
          const bool  same_kind = ca.is_prescribed() ? cb.is_prescribed() : ca.is_initial() && ca.type == cb.type;
          if (!same_kind || ca.component != cb.component)
            continue;
          const auto common = [](const std::vector<unsigned int> &x, const std::vector<unsigned int> &y) {
            std::vector<unsigned int> sx(x), sy(y), both;
            std::sort(sx.begin(), sx.end());
            std::sort(sy.begin(), sy.end());
            std::set_intersection(sx.begin(), sx.end(), sy.begin(), sy.end(), std::back_inserter(both));
            return both.size();
          };
          const auto n = Utilities::MPI::sum(common(ca.points, cb.points) + common(ca.nodes, cb.nodes), comm);
          if (n > 0)
            record.warnings.push_back("boundary conditions '" + ca.name + "' and '" + cb.name + "' both " +
                               (ca.is_prescribed() ? "prescribe" : "set the initial value of") + " component " +
                               std::string(1, char('x' + ca.component)) + " at " + std::to_string(n) +
                               " points; there the later one in Boundary conditions/Names ('" + cb.name +
                               "') replaces '" + ca.name + "': make their regions disjoint if that is not meant");
        }
    constraints.clear();
    {
      // A later condition on the same component of the same point wins.
      std::map<std::pair<unsigned int, unsigned int>, unsigned int> owner;
      for (unsigned int c = 0; c < conditions.size(); ++c)
        if (conditions[c].is_prescribed())
          for (const unsigned int i : conditions[c].points)
            owner[{i, conditions[c].component}] = c;
      for (const auto &[key, c] : owner)
        constraints.push_back({key.first, key.second, c});
      constraint_force.assign(constraints.size(), 0.0);
    }
    node_constraints.clear();
    if (has_continuum)
      {
        std::map<unsigned int, unsigned int> owner;
        for (unsigned int c = 0; c < conditions.size(); ++c)
          if (conditions[c].is_prescribed())
            for (const unsigned int k : conditions[c].nodes)
              owner[k] = c;
        for (const auto &[k, c] : owner)
          node_constraints.push_back({k, c});
        node_constraint_force.assign(node_constraints.size(), 0.0);
      }
    body_force.clear();
    loads_depend_on_time = false;
    for (const auto &bc : conditions)
      if (bc.is_load())
        {
          if (bc.type == BoundaryCondition::Type::body_force)
            body_force.resize(dim * cloud.n_owned(), 0.0);
          loads_depend_on_time |= bc.value->depends_on_time();
          if (has_continuum && continuum->load.size() == 0)
            continuum->load.reinit(continuum->F);
        }
  }

  void
  ConditionSet::apply_initial_conditions(const double initial_time)
  {
    state.displacement = 0;
    state.velocity     = 0;
    for (const auto &bc : conditions)
      if (bc.is_initial() || bc.is_prescribed())
        {
          VectorType &target = (bc.type == BoundaryCondition::Type::initial_velocity ||
                                bc.type == BoundaryCondition::Type::prescribed_velocity) ?
                                 state.velocity :
                                 state.displacement;
          for (const unsigned int i : bc.points)
            target.local_element(dim * i + bc.component) =
              bc.value->value(cloud.position(i), initial_time, cloud.hash(i));
          if (has_continuum)
            {
              ContinuumField::VectorType &fe_target = &target == &state.velocity ? continuum->V : continuum->U;
              for (const unsigned int k : bc.nodes)
                fe_target.local_element(continuum->nodes[k].local) =
                  bc.value->value(continuum->nodes[k].x, initial_time, 0);
            }
        }
    if (has_continuum && continuum->hanging.n_constraints() > 0)
      {
        continuum->hanging.distribute(continuum->U);
        continuum->hanging.distribute(continuum->V);
      }
    // Where the prescribed velocities start from (apply_prescribed).
    constraint_displacement.resize(constraints.size());
    for (unsigned int k = 0; k < constraints.size(); ++k)
      constraint_displacement[k] = state.displacement.local_element(dim * constraints[k].point + constraints[k].component);
    node_constraint_displacement.resize(node_constraints.size());
    for (unsigned int k = 0; k < node_constraints.size(); ++k)
      node_constraint_displacement[k] = continuum->U.local_element(continuum->nodes[node_constraints[k].node].local);
    evaluate_loads(initial_time);
    check_condition_values(first_nonfinite_condition(initial_time), initial_time);
  }

  void
  ConditionSet::evaluate_loads(const double time)
  {
    const bool fe_loads = has_continuum && continuum->load.size() > 0;
    if (body_force.empty() && !fe_loads)
      return;
    std::fill(body_force.begin(), body_force.end(), 0.0);
    if (fe_loads)
      continuum->load = 0;
    for (const auto &bc : conditions)
      if (bc.type == BoundaryCondition::Type::traction)
        continuum->add_face_load(bc.faces, bc.component,
                                 [&](const Point<dim> &x) { return bc.value->value(x, time, 0); });
      else if (bc.type == BoundaryCondition::Type::body_force)
        {
          for (const unsigned int i : bc.points)
            body_force[dim * i + bc.component] += bc.value->value(cloud.position(i), time, cloud.hash(i));
          // FE nodes: b(x_a) int N_a, i.e. the lumped mass over the density
          // (exact for a constant b).
          for (const unsigned int k : bc.nodes)
            {
              const auto &node = continuum->nodes[k];
              continuum->load.local_element(node.local) +=
                bc.value->value(node.x, time, 0) * continuum->mass.local_element(node.local) / (*node_density)[k];
            }
        }
    if (fe_loads)
      continuum->load.compress(VectorOperation::add);
  }

  unsigned int
  ConditionSet::first_nonfinite_condition(const double time) const
  {
    for (unsigned int c = 0; c < conditions.size(); ++c)
      for (const unsigned int i : conditions[c].points)
        if (!std::isfinite(conditions[c].value->value(cloud.position(i), time, cloud.hash(i))))
          return c + 1;
    return 0;
  }

  void
  ConditionSet::check_condition_values(const unsigned int bad_local, const double time) const
  {
    // Collective: the offending point may live on one rank only.
    const unsigned int bad = Utilities::MPI::max(bad_local, comm);
    if (bad == 0)
      return;
    // The expressions remember where they first failed: name that point.
    std::vector<const Expression *> values;
    for (const auto &bc : conditions)
      values.push_back(bc.value.get());
    check_finite(values, comm);
    AssertThrow(false,
                ExcMessage("Boundary conditions/" + conditions[bad - 1].name + "/Value: '" +
                           conditions[bad - 1].value->text() + "' is not finite at some of its points at t = " +
                           sci(time, 6)));
  }

  void
  ConditionSet::apply_prescribed(const double time, const double step_dt)
  {
    // One prescribed entry (u, v) at x for the step that ends at time. A
    // prescribed velocity integrates its own displacement (midpoint rule) in
    // @p own and assigns it: the integrators may have moved u already (the
    // Verlet drift, Newmark's predictor), which must not count twice.
    const auto prescribe = [&](const unsigned int condition, const Point<dim> &x, const std::uint64_t h, double &u,
                               double &v, double &own) {
      const BoundaryCondition &bc = conditions[condition];
      if (bc.type == BoundaryCondition::Type::prescribed_displacement)
        {
          const double now = bc.value->value(x, time, h);
          v                = (now - bc.value->value(x, time - step_dt, h)) / step_dt;
          u                = now;
        }
      else
        {
          own += step_dt * bc.value->value(x, time - 0.5 * step_dt, h);
          u = own;
          v = bc.value->value(x, time, h);
        }
      if (!std::isfinite(u) || !std::isfinite(v))
        bad_condition = condition + 1;
    };
    for (unsigned int k = 0; k < constraints.size(); ++k)
      {
        const Constraint  &c = constraints[k];
        const unsigned int e = dim * c.point + c.component;
        prescribe(c.condition, cloud.position(c.point), cloud.hash(c.point), state.displacement.local_element(e),
                  state.velocity.local_element(e), constraint_displacement[k]);
      }
    for (unsigned int k = 0; k < node_constraints.size(); ++k)
      {
        const ContinuumField::Node &node = continuum->nodes[node_constraints[k].node];
        prescribe(node_constraints[k].condition, node.x, 0, continuum->U.local_element(node.local),
                  continuum->V.local_element(node.local), node_constraint_displacement[k]);
      }
  }

  std::vector<std::uint8_t>
  ConditionSet::fe_prescribed_flags() const
  {
    std::vector<std::uint8_t> flags(continuum->U.locally_owned_size(), 0);
    for (const auto &c : node_constraints)
      flags[continuum->nodes[c.node].local] = 1;
    return flags;
  }

  double
  ConditionSet::support_force(const Constraint &c) const
  {
    const unsigned int k = dim * c.point + c.component;
    return (state.acceleration.empty() ? 0.0 : state.mass_density[c.point] * cloud.volume[c.point] * state.acceleration[k]) -
           cloud.volume[c.point] * state.force.local_element(k);
  }

  double
  ConditionSet::node_support_force(const NodeConstraint &c) const
  {
    const unsigned int l = continuum->nodes[c.node].local;
    return (state.fe_acceleration.empty() ? 0.0 : continuum->mass.local_element(l) * state.fe_acceleration[l]) -
           continuum->F.local_element(l);
  }
} // namespace perideal
