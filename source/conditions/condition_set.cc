// The conditions as sets of degrees of freedom (condition_set.h).

#include <perideal/base/expression.h>
#include <perideal/base/format.h>
#include <perideal/conditions/condition_set.h>
#include <perideal/output/checkpoint.h>
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
    continuum    = coupling ? &coupling->continuum : nullptr;
    node_density = coupling ? &coupling->node_density : nullptr;
    // Conditions: their points, the constraints, the body force.
    for (auto &bc : conditions)
      {
        bc.faces.clear();
        if (bc.type == BoundaryCondition::Type::traction)
          {
            find_traction_faces(bc);
            continue;
          }
        // The points as before a conversion where they are unchanged; the
        // FE nodes asked again (deal.II numbers every DoF again).
        std::vector<unsigned int> before;
        for (const auto dof : bc.dofs)
          if (dof < point_entries_then)
            before.push_back(dof / dim);
        bc.dofs.clear();
        for (const unsigned int i : discretization.points_in_region(bc.region, before))
          bc.dofs.push_back(dim * i + bc.component);
        if (continuum)
          for (const auto &node : continuum->nodes)
            if (node.component == bc.component && discretization.in_region(bc.region, node.x, node.cell))
              bc.dofs.push_back(state.point_entries() + node.local);
        if (Utilities::MPI::sum(bc.dofs.size(), comm) == 0)
          record.warnings.push_back("boundary condition '" + bc.name + "' acts on no point (region '" +
                             bc.region + "' is empty)");
      }
    point_entries_then = state.point_entries();
  }

  void
  ConditionSet::find_traction_faces(BoundaryCondition &bc) const
  {
    const auto selected = [&](const CellIterator &cell, const unsigned int f) {
      return cell->face(f)->at_boundary() &&
             (bc.boundary_id >= 0 ? cell->face(f)->boundary_id() == types::boundary_id(bc.boundary_id) :
                                    discretization.in_region(bc.region, cell->face(f)->center(), cell));
    };
    // An FE cell's faces take the traction through its shape functions.
    bc.dofs.clear();
    if (continuum != nullptr)
      for (const auto &cell : discretization.dof_handler.active_cell_iterators())
        if (cell->is_locally_owned() && discretization.is_fe_cell(cell))
          for (const unsigned int f : cell->face_indices())
            if (selected(cell, f))
              bc.faces.emplace_back(cell, f);
    // A PD cell's faces load its point with traction x area, the force the
    // FE face carried: a cell that converts keeps its load.
    bc.point_faces.clear();
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (!discretization.is_virtual(i) && !cloud.is_extra(i) && !discretization.is_fe_cell(cloud.cell[i]))
        for (const unsigned int f : cloud.cell[i]->face_indices())
          if (selected(cloud.cell[i], f))
            bc.point_faces.push_back({i, cloud.cell[i]->face(f)->measure(), cloud.cell[i]->face(f)->center()});
    bc.on_points = Utilities::MPI::logical_or(!bc.point_faces.empty(), comm);
    if (Utilities::MPI::sum(bc.faces.size() + bc.point_faces.size(), comm) == 0)
      record.warnings.push_back("traction '" + bc.name + "' acts on no boundary face");
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
          const auto n = Utilities::MPI::sum(common(ca.dofs, cb.dofs), comm);
          if (n > 0)
            record.warnings.push_back("boundary conditions '" + ca.name + "' and '" + cb.name + "' both " +
                               (ca.is_prescribed() ? "prescribe" : "set the initial value of") + " component " +
                               std::string(1, char('x' + ca.component)) + " at " + std::to_string(n) +
                               " points; there the later one in Boundary conditions/Names ('" + cb.name +
                               "') replaces '" + ca.name + "': make their regions disjoint if that is not meant");
        }
    constraints.clear();
    {
      // A later condition on the same DoF wins.
      std::map<unsigned int, unsigned int> owner;
      for (unsigned int c = 0; c < conditions.size(); ++c)
        if (conditions[c].is_prescribed())
          for (const unsigned int k : conditions[c].dofs)
            owner[k] = c;
      prescribed.assign(state.size(), 0);
      for (const auto &[k, c] : owner)
        {
          constraints.push_back({k, c});
          prescribed[k] = 1;
        }
      constraint_force.assign(constraints.size(), 0.0);
    }
    body_force.clear();
    loads_depend_on_time = false;
    for (const auto &bc : conditions)
      if (bc.is_load())
        {
          if (bc.type == BoundaryCondition::Type::body_force || bc.on_points)
            body_force.resize(state.point_entries(), 0.0);
          loads_depend_on_time |= bc.value->depends_on_time();
          if (continuum && continuum->load.size() == 0)
            continuum->load.reinit(continuum->F);
        }
    fe_load = continuum && continuum->load.size() > 0 ? continuum->load.begin() : nullptr;
  }

  void
  ConditionSet::take_constraint_state()
  {
    constraint_force.resize(constraints.size());
    constraint_displacement.resize(constraints.size());
    for (unsigned int c = 0; c < constraints.size(); ++c)
      {
        constraint_force[c]        = state.f(constraints[c].dof);
        constraint_displacement[c] = state.u(constraints[c].dof);
      }
  }

  void
  ConditionSet::keep_integrated(const std::vector<double> &integrated)
  {
    for (unsigned int c = 0; c < constraints.size(); ++c)
      if (conditions[constraints[c].condition].type == BoundaryCondition::Type::prescribed_velocity)
        {
          constraint_displacement[c]   = integrated[c];
          state.u(constraints[c].dof) = integrated[c];
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
          const bool velocity = bc.type == BoundaryCondition::Type::initial_velocity ||
                                bc.type == BoundaryCondition::Type::prescribed_velocity;
          for (const unsigned int k : bc.dofs)
            (velocity ? state.v(k) : state.u(k)) = bc.value->value(state.position(k), initial_time, state.hash(k));
        }
    state.distribute_displacement();
    state.distribute_velocity();
    // Where the prescribed velocities start from (apply_prescribed).
    constraint_displacement.resize(constraints.size());
    for (unsigned int c = 0; c < constraints.size(); ++c)
      constraint_displacement[c] = state.u(constraints[c].dof);
    evaluate_loads(initial_time);
    check_condition_values(first_nonfinite_condition(initial_time), initial_time);
  }

  void
  ConditionSet::evaluate_loads(const double time)
  {
    if (!has_loads())
      return;
    std::fill(body_force.begin(), body_force.end(), 0.0);
    if (fe_load)
      continuum->load = 0;
    for (const auto &bc : conditions)
      if (bc.type == BoundaryCondition::Type::traction)
        {
          if (continuum)
            continuum->add_face_load(bc.faces, bc.component,
                                     [&](const Point<dim> &x) { return bc.value->value(x, time, 0); });
          for (const auto &face : bc.point_faces)
            body_force[dim * face.point + bc.component] +=
              bc.value->value(face.center, time, 0) * face.area / cloud.volume[face.point];
        }
      else if (bc.type == BoundaryCondition::Type::body_force)
        for (const unsigned int k : bc.dofs)
          {
            const double b = bc.value->value(state.position(k), time, state.hash(k));
            // FE DoFs: b(x_a) int N_a, i.e. the lumped mass over the density
            // (exact for a constant b).
            if (state.is_fe(k))
              continuum->load.local_element(state.fe_local(k)) +=
                b * state.density(k) / (*node_density)[state.fe_node(k)];
            else
              body_force[k] += b;
          }
    if (fe_load)
      continuum->load.compress(VectorOperation::add);
  }

  unsigned int
  ConditionSet::first_nonfinite_condition(const double time) const
  {
    for (unsigned int c = 0; c < conditions.size(); ++c)
      for (const unsigned int k : conditions[c].dofs)
        if (!std::isfinite(conditions[c].value->value(state.position(k), time, state.hash(k))))
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
    for (unsigned int c = 0; c < constraints.size(); ++c)
      {
        const unsigned int k = constraints[c].dof;
        prescribe(constraints[c].condition, state.position(k), state.hash(k), state.u(k), state.v(k),
                  constraint_displacement[c]);
      }
  }

  double
  ConditionSet::support_force(const Constraint &c) const
  {
    const unsigned int k = c.dof;
    return (state.acceleration.empty() ? 0.0 : state.mass(k) * state.acceleration[k]) - state.measure(k) * state.f(k);
  }

  void
  ConditionSet::save(CheckpointWriter &out) const
  {
    out.section("conditions");
    out.put(constraint_force);
    out.put(constraint_displacement);
  }

  void
  ConditionSet::load(CheckpointReader &in)
  {
    in.section("conditions");
    const std::size_t n = constraints.size();
    in.get(constraint_force);
    in.get(constraint_displacement);
    in.expect(constraint_displacement.size() == n && (constraint_force.empty() || constraint_force.size() == n),
              "this rank has " + std::to_string(n) + " constrained degrees of freedom, the checkpoint " +
                std::to_string(constraint_displacement.size()));
  }
} // namespace perideal
