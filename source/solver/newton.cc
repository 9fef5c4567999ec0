// Newton's method for one implicit step (implicit_solver.h): set-up of the
// tangent and the prescribed DoFs, the residual, the tangent's assembly, the
// solve with its line search and the re-solves while bonds break, the load
// path's work; and what QuasiStatic and Newmark share (ImplicitIntegrator).

#include <perideal/adaptivity/adaptivity.h>
#include <perideal/base/best_point.h>
#include <perideal/base/format.h>
#include <perideal/base/interrupt.h>
#include <perideal/continuum/coupling.h>
#include <perideal/model/force_model.h>
#include <perideal/output/postprocess.h>
#include <perideal/simulation/deck.h>
#include <perideal/output/checkpoint.h>
#include <perideal/solver/implicit_solver.h>
#include <perideal/solver/rigid_modes.h>

#include <deal.II/base/mpi.h>

#include <array>
#include <cmath>
#include <limits>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    /// Whether the material of every deformable block has an analytic
    /// tangent: Material::add_tangent() returns false if it has none, and on
    /// no points it adds nothing to @p rows and answers just that.
    bool
    analytic_tangents(const SimulatorAccess &access, TangentRows &rows)
    {
      const ModelState state{access.discretization.cloud,
                             access.discretization.bonds,
                             nullptr,
                             access.state.displacement.begin(),
                             nullptr,
                             nullptr,
                             access.model.field_store()};
      for (const auto &b : access.model.blocks)
        if (!b.rigid && !b.material->add_tangent(state, {}, rows))
          return false;
      return true;
    }
  } // namespace

  ImplicitSolver::ImplicitSolver(const SimulatorAccess &access, const ImplicitParameters &parameters)
    : access(access)
    , implicit(parameters)
    , comm(access.comm)
    , pcout(access.pcout)
    , timer(access.timer)
    , cloud(access.discretization.cloud)
    , state(access.state)
    , continuum(access.coupling ? &access.coupling->continuum : nullptr)
    , has_continuum(access.coupling != nullptr)
    , force_blending(has_continuum && access.discretization.force_blending)
    // Force blending's tangent is not symmetric (coupled_tangent.h).
    , linear_solver(force_blending ? std::string("GMRES") : implicit.linear_solver)
  {}

  std::vector<std::pair<Point<3>, unsigned int>>
  ImplicitSolver::collect_unknowns()
  {
    // The unknowns (with continuum blocks: the free DoFs of real points and
    // FE nodes, coupled_tangent.h; without: every owned PD DoF, prescribed
    // ones with identity rows), by position and component: the rigid-body
    // modes about their centroid are the AMG's near null space and the
    // motions some condition must remove.
    std::vector<std::pair<Point<dim>, unsigned int>> unknowns;
    const std::vector<std::uint8_t>                 &held = access.conditions.prescribed;
    unknown_dofs.clear();
    pd_free.clear();
    fe_free.clear();
    if (has_continuum)
      state.for_each([&](const MechanicalState::DoF &d) {
        if (!held[d.number] && !is_pinned(d.number) && !state.is_virtual(d.number))
          {
            unknown_dofs.push_back(d.number);
            (state.is_fe(d.number) ? fe_free : pd_free)
              .push_back(state.is_fe(d.number) ? state.fe_local(d.number) : d.number);
          }
      });
    else
      for (unsigned int k = 0; k < dim * cloud.n_owned(); ++k)
        unknown_dofs.push_back(k);
    for (const unsigned int k : unknown_dofs)
      unknowns.emplace_back(state.position(k), state.component(k));
    return unknowns;
  }

  std::pair<std::array<double, 3>, double>
  ImplicitSolver::centre_and_extent(const std::vector<std::pair<Point<3>, unsigned int>> &unknowns) const
  {
    std::array<double, dim>     centre{{0, 0, 0}};
    std::array<double, dim + 1> s{{0, 0, 0, 0}};
    for (const auto &[x, c] : unknowns)
      {
        for (unsigned int d = 0; d < dim; ++d)
          s[d] += x[d];
        s[dim] += 1;
      }
    Utilities::MPI::sum(ArrayView<const double>(s.data(), s.size()), comm, ArrayView<double>(s.data(), s.size()));
    for (unsigned int d = 0; d < dim; ++d)
      centre[d] = s[dim] > 0 ? s[d] / s[dim] : 0.0;
    double extent = 0;
    for (const auto &[p, c] : unknowns)
      for (unsigned int d = 0; d < dim; ++d)
        extent = std::max(extent, std::abs(p[d] - centre[d]));
    return {centre, Utilities::MPI::max(extent, comm)};
  }

  namespace
  {
    /// A load whose component along a free rigid-body motion exceeds this
    /// fraction of its norm (both as force vectors over the unknowns, the
    /// motion of unit length) excites the motion: a body in equilibrium
    /// under it would have to be held. Round-off in a balanced load is
    /// about 1e-16 of it; a load that is meant to balance but is written
    /// with few digits is caught above 1e-8.
    constexpr double free_mode_tolerance = 1e-8;
  } // namespace

  void
  ImplicitSolver::check_supports(const std::vector<std::pair<Point<3>, unsigned int>> &unknowns) const
  {
    // A motion is removed if a prescribed entry moves with it; a hinge or
    // a single held point leaves combinations of the coordinate modes free.
    std::vector<std::pair<Point<dim>, unsigned int>> prescribed;
    for (const auto &c : access.conditions.constraints)
      prescribed.emplace_back(state.position(c.dof), state.component(c.dof));
    const auto [centre, extent] = centre_and_extent(unknowns);
    std::vector<std::array<double, 6>> modes;
    const std::vector<std::string> names = free_rigid_modes(prescribed, centre, extent, comm, &modes);
    std::string free_modes;
    for (const auto &mode : names)
      free_modes += (free_modes.empty() ? "" : ", ") + mode;
    // With continuum blocks the unknowns are the coupled tangent's and the
    // motions are not projected out of its solve.
    AssertThrow(free_modes.empty() || !has_continuum,
                ExcMessage("the quasistatic problem is singular: no boundary condition removes the rigid-body "
                           "motion(s) " + free_modes + ". Prescribe displacements (Type = Prescribed "
                           "displacement) on regions that hold the body in place (with continuum blocks a free "
                           "motion is not projected out of the solve)"));
    if (free_modes.empty())
      return;
    // Without: solved with them projected out, if the loads leave them
    // alone; the loads of the current time are checked here (the run's
    // start: a stage is refused before any solver runs), each load step's
    // in check_free_mode_loads().
    std::vector<std::vector<double>> named(names.size());
    for (unsigned int m = 0; m < names.size(); ++m)
      named[m] = free_mode_vector(unknowns, centre, extent, modes[m]);
    const double t0 = access.deck.solver.initial_time;
    if (access.conditions.has_loads())
      access.conditions.evaluate_loads(t0); // as the solver starting there will
    check_free_mode_loads(names, named, "at t = " + sci(t0, 6));
  }

  std::vector<double>
  ImplicitSolver::free_mode_vector(const std::vector<std::pair<Point<3>, unsigned int>> &unknowns,
                                   const std::array<double, 3> &centre, const double extent,
                                   const std::array<double, 6> &mode) const
  {
    // Zero at prescribed entries (a free motion leaves them in place) and
    // at pinned ones (their rows of K are the identity's).
    const std::vector<std::uint8_t> &held = access.conditions.prescribed;
    std::vector<double>              z(unknowns.size(), 0.0);
    for (unsigned int j = 0; j < unknowns.size(); ++j)
      {
        const unsigned int k = unknown_dofs[j];
        if (held[k] || is_pinned(k))
          continue;
        const auto &[p, c] = unknowns[j];
        for (unsigned int m = 0; m < 6; ++m)
          z[j] += mode[m] * rigid_mode_value(m, c, p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]) /
                  (m < 3 ? 1 : extent);
      }
    return z;
  }

  void
  ImplicitSolver::check_free_mode_loads(const std::vector<std::string>         &names,
                                        const std::vector<std::vector<double>> &named,
                                        const std::string                      &when) const
  {
    if (names.empty())
      return;
    // Per motion: z.L and |z|^2; and |L|^2. L = V b on the free unknowns
    // (a load on a prescribed entry is its support's).
    const std::vector<std::uint8_t> &held = access.conditions.prescribed;
    const bool                       loads = access.conditions.has_loads();
    std::vector<double>              sums(2 * names.size() + 1, 0.0);
    for (unsigned int j = 0; j < unknown_dofs.size(); ++j)
      {
        const unsigned int k = unknown_dofs[j];
        const double       L = loads && !held[k] && !is_pinned(k) ? state.measure(k) * access.conditions.load(k) : 0.0;
        for (unsigned int m = 0; m < names.size(); ++m)
          {
            sums[2 * m] += named[m][j] * L;
            sums[2 * m + 1] += named[m][j] * named[m][j];
          }
        sums.back() += L * L;
      }
    Utilities::MPI::sum(sums, comm, sums);
    const double load_norm = std::sqrt(sums.back());
    std::string  excited, all;
    double       largest = 0;
    for (unsigned int m = 0; m < names.size(); ++m)
      {
        all += (all.empty() ? "" : ", ") + names[m];
        const double part = std::abs(sums[2 * m]) / (std::sqrt(sums[2 * m + 1]) * load_norm);
        if (load_norm > 0 && sums[2 * m + 1] > 0 && part > free_mode_tolerance)
          {
            excited += (excited.empty() ? "" : ", ") + names[m];
            largest = std::max(largest, part);
          }
      }
    AssertThrow(excited.empty(),
                ExcMessage("the quasistatic problem is singular: no boundary condition removes the rigid-body "
                           "motion(s) " + all + ", and " + when + " the loads push the body along " + excited +
                           " (their component along it is " + sci(largest, 3) + " of their norm, above " +
                           sci(free_mode_tolerance, 1) + "): no equilibrium holds it. Prescribe displacements "
                           "(Type = Prescribed displacement) on regions that hold the body in place, or balance "
                           "the loads"));
  }

  void
  ImplicitSolver::check_free_mode_loads(const unsigned int step) const
  {
    check_free_mode_loads(free_names, free_named, "at load step " + std::to_string(step));
  }

  void
  ImplicitSolver::setup_free_modes(const std::vector<std::pair<Point<3>, unsigned int>> &unknowns)
  {
    free_names.clear();
    free_named.clear();
    free_basis.clear();
    mode_pins.clear();
    if (has_continuum)
      return; // check_supports() refused them
    std::vector<std::pair<Point<dim>, unsigned int>> prescribed;
    for (const auto &c : access.conditions.constraints)
      prescribed.emplace_back(state.position(c.dof), state.component(c.dof));
    const auto [centre, extent] = centre_and_extent(unknowns);
    std::vector<std::array<double, 6>> modes;
    free_names = free_rigid_modes(prescribed, centre, extent, comm, &modes);
    if (free_names.empty())
      return;
    const unsigned int n = unknowns.size(), m = free_names.size();
    for (unsigned int i = 0; i < m; ++i)
      free_named.push_back(free_mode_vector(unknowns, centre, extent, modes[i]));
    // An orthonormal basis (modified Gram-Schmidt, twice for round-off).
    free_basis = free_named;
    for (unsigned int i = 0; i < m; ++i)
      for (unsigned int pass = 0; pass < 2; ++pass)
        {
          for (unsigned int l = 0; l < i; ++l)
            {
              double dot = 0;
              for (unsigned int j = 0; j < n; ++j)
                dot += free_basis[i][j] * free_basis[l][j];
              dot = Utilities::MPI::sum(dot, comm);
              for (unsigned int j = 0; j < n; ++j)
                free_basis[i][j] -= dot * free_basis[l][j];
            }
          double norm = 0;
          for (const double x : free_basis[i])
            norm += x * x;
          norm = std::sqrt(Utilities::MPI::sum(norm, comm));
          AssertThrow(norm > 0, ExcInternalError());
          for (double &x : free_basis[i])
            x /= norm;
        }
    // One unknown per motion held at 0 in each linear solve makes K
    // regular: Gaussian elimination with full pivoting over the basis
    // vectors picks them (the largest remaining entry, the smallest global
    // id on ties), so the held entries determine the motion well.
    std::vector<std::vector<double>> rest = free_basis;
    std::vector<std::uint8_t>        taken(n, 0);
    for (unsigned int i = 0; i < m; ++i)
      {
        BestPoint best(BestPoint::Order::largest);
        for (unsigned int j = 0; j < n; ++j)
          if (!taken[j] && unknown_dofs[j] < state.point_entries())
            {
              const unsigned int k = unknown_dofs[j];
              const double       x[3] = {double(j), 0, 0};
              best.consider(std::abs(rest[i][j]), dim * cloud.gid[k / dim] + k % dim, x);
            }
        const BestPoint pick = best.global(comm);
        AssertThrow(pick.found && pick.value > 1e-8, ExcInternalError());
        // The owner broadcasts the pivot row: every vector's entry there.
        std::vector<double> row(m, 0.0);
        const bool          mine = best.found && best.id == pick.id;
        const unsigned int  jp   = mine ? static_cast<unsigned int>(best.x[0]) : 0;
        if (mine)
          {
            taken[jp] = 1;
            mode_pins.push_back(jp);
            for (unsigned int l = 0; l < m; ++l)
              row[l] = rest[l][jp];
          }
        Utilities::MPI::sum(row, comm, row);
        for (unsigned int l = i + 1; l < m; ++l)
          {
            const double f = row[l] / row[i];
            for (unsigned int j = 0; j < n; ++j)
              rest[l][j] -= f * rest[i][j];
          }
      }
    pcout << "  free rigid-body motions: " << m << " (";
    for (unsigned int i = 0; i < m; ++i)
      pcout << (i ? ", " : "") << free_names[i];
    pcout << "): no condition removes them and the loads leave them alone; solved with them projected out "
             "(the displacement has no part along them)" << std::endl;
  }

  void
  ImplicitSolver::project_free_modes(double *v) const
  {
    const unsigned int  m = free_basis.size(), n = unknown_dofs.size();
    if (m == 0)
      return;
    std::vector<double> c(m, 0.0);
    for (unsigned int i = 0; i < m; ++i)
      for (unsigned int j = 0; j < n; ++j)
        c[i] += free_basis[i][j] * v[j];
    Utilities::MPI::sum(c, comm, c);
    for (unsigned int i = 0; i < m; ++i)
      for (unsigned int j = 0; j < n; ++j)
        v[j] -= c[i] * free_basis[i][j];
  }

  void
  ImplicitSolver::check_supports()
  {
    check_supports(collect_unknowns());
  }

  void
  ImplicitSolver::check_pinned_loads(const unsigned int step) const
  {
    if (n_pinned == 0 || !access.conditions.has_loads())
      return;
    // A point without bonds under a load has no quasistatic equilibrium.
    BestPoint loaded(BestPoint::Order::largest);
    for (unsigned int k = 0; k < pinned.size(); ++k)
      if (pinned[k] && access.conditions.load(k) != 0)
        loaded.consider(std::abs(access.conditions.load(k)), cloud.gid[k / dim], &cloud.X[dim * (k / dim)]);
    const BestPoint p = loaded.global(comm);
    AssertThrow(!p.found,
                ExcMessage("load step " + std::to_string(step) + ": the quasistatic problem has no equilibrium: the " +
                           p.describe() + " has no bond (no neighbor within the horizon) and carries a body force "
                           "of " + sci(p.value) + " (per unit volume, in one component): nothing holds it against "
                           "the load. Bond it (a larger horizon), prescribe its displacement, or use an explicit "
                           "solver (Type = Verlet), in which it moves freely"));
  }

  void
  ImplicitSolver::setup(const bool need_supports)
  {
    unsigned int hops = 1;
    for (const auto &b : access.model.blocks)
      hops = std::max(hops, b.material->coupling_hops());

    // Which local degrees of freedom are prescribed (ghosts from their owners).
    const unsigned int n_owned = cloud.n_owned();
    // A quasistatic solve holds the free entries of a point without bonds
    // where they are (its rows of K are empty): identity rows as at a
    // support, no residual; a load on one has no equilibrium (check_pinned_loads()).
    pinned.assign(need_supports ? dim * n_owned : 0, 0);
    n_pinned = 0;
    if (need_supports)
      for (unsigned int i = 0; i < n_owned; ++i)
        if (access.discretization.bonds.offsets[i + 1] == access.discretization.bonds.offsets[i] &&
            !state.is_virtual(dim * i))
          for (unsigned int c = 0; c < dim; ++c)
            if (!access.conditions.prescribed[dim * i + c])
              {
                pinned[dim * i + c] = 1;
                ++n_pinned;
              }
    n_pinned = Utilities::MPI::sum(n_pinned, comm);
    {
      VectorType flags(cloud.vector_partitioner);
      for (const auto &c : access.conditions.constraints)
        if (!state.is_fe(c.dof))
          flags.local_element(c.dof) = 1;
      for (unsigned int k = 0; k < pinned.size(); ++k)
        if (pinned[k])
          flags.local_element(k) = 1;
      flags.update_ghost_values();
      constrained_dofs.assign(dim * cloud.n_local(), 0);
      for (unsigned int k = 0; k < dim * cloud.n_local(); ++k)
        constrained_dofs[k] = flags.local_element(k) != 0;
    }

    const std::vector<std::pair<Point<dim>, unsigned int>> unknowns = collect_unknowns();
    if (need_supports)
      {
        check_supports(unknowns);
        setup_free_modes(unknowns);
        // The motions' pins are held like supports in the linear solves.
        if (!free_names.empty())
          {
            VectorType flags(cloud.vector_partitioner);
            for (unsigned int k = 0; k < dim * n_owned; ++k)
              flags.local_element(k) = constrained_dofs[k];
            for (const unsigned int j : mode_pins)
              flags.local_element(unknown_dofs[j]) = 1;
            flags.update_ghost_values();
            for (unsigned int k = 0; k < dim * cloud.n_local(); ++k)
              constrained_dofs[k] = flags.local_element(k) != 0;
          }
      }
    const auto [centre, extent] = centre_and_extent(unknowns);
    const unsigned int n = unknowns.size();
    rigid_modes.assign(6 * n, 0.0);
    for (unsigned int k = 0; k < n; ++k)
      {
        const auto &[p, c] = unknowns[k];
        for (unsigned int mode = 0; mode < 6; ++mode)
          rigid_modes[mode * n + k] = rigid_mode_value(mode, c, p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]);
      }
    {
      TimerOutput::Scope t(timer, "implicit: sparsity");
      tangent = std::make_unique<Tangent>();
      if (implicit.jacobian == "Matrix free")
        tangent->reinit_diagonal(cloud, hops, comm);
      else
        tangent->reinit(cloud, access.discretization.bonds, hops, comm);
      if (has_continuum)
        {
          coupled_tangent = std::make_unique<CoupledTangent>();
          const std::vector<NodeRow> node_rows = access.coupling->node_rows(cloud);
          coupled_tangent->reinit(force_blending ? &node_rows : nullptr, pd_free, fe_free, access.coupling->virtual_points, continuum->interpolation(), tangent->owned,
                                  continuum->vector_partitioner(), continuum->stiffness(), comm);
          symmetry_reported = false;
        }
    }
    use_finite_differences = implicit.tangent == "Finite differences";
    // A material without an analytic tangent (the correspondence models)
    // makes every solve use finite differences: decided here, so that the
    // set-up line names the tangent the solves use.
    if (!use_finite_differences && implicit.jacobian == "Assembled" && !analytic_tangents(access, tangent->begin(constrained_dofs)))
      {
        use_finite_differences = true;
        access.record.warnings.push_back("a material has no analytic tangent: the implicit solver uses finite differences");
      }
    fd_step                = std::numeric_limits<double>::max();
    for (unsigned int i = 0; i < n_owned; ++i)
      fd_step = std::min(fd_step, 1e-6 * std::cbrt(cloud.volume[i]));
    fd_step = Utilities::MPI::min(fd_step, comm);
  }

  double
  ImplicitSolver::residual(std::vector<double> &R, double &force_norm)
  {
    TimerOutput::Scope t(timer, "implicit: residual");
    state.distribute_displacement();
    access.update_ghosts();
    access.model.compute_forces(false);
    // The unknowns' rows (prescribed ones 0): V f at points, the FE nodal
    // force Pi^T (V f) - K U + load; the force scale over every real point
    // entry and FE DoF, supports included.
    double free = 0, all = 0;
    const std::vector<std::uint8_t> &held = access.conditions.prescribed;
    for (unsigned int j = 0; j < unknown_dofs.size(); ++j)
      {
        const unsigned int k = unknown_dofs[j];
        double             r = state.measure(k) * state.f(k);
        if (newmark_inertia > 0)
          r -= state.mass(k) * newmark_inertia * (state.u(k) - u_predicted[k]);
        R[j] = held[k] || is_pinned(k) ? 0 : r;
        free += R[j] * R[j];
      }
    state.for_each([&](const MechanicalState::DoF &d) {
      const double F = d.measure * d.f;
      if (!state.is_virtual(d.number))
        all += F * F;
    });
    if (!free_basis.empty())
      {
        // No part along the free motions: the loads leave them alone
        // (check_free_mode_loads()), and what the internal forces put there
        // (round-off; the moment of the forces about the displaced points) is
        // no equation.
        project_free_modes(R.data());
        free = 0;
        for (unsigned int j = 0; j < unknown_dofs.size(); ++j)
          free += R[j] * R[j];
      }
    double sums[2] = {free, all};
    Utilities::MPI::sum(ArrayView<const double>(sums, 2), comm, ArrayView<double>(sums, 2));
    force_norm = std::sqrt(sums[1]);
    return std::sqrt(sums[0]);
  }

  void
  ImplicitSolver::assemble_tangent()
  {
    TimerOutput::Scope t(timer, "implicit: tangent");
    TangentRows       &rows = tangent->begin(constrained_dofs);
    if (implicit.jacobian == "Matrix free")
      {
        const unsigned int missing = access.model.add_tangent(rows) ? 0 : 1;
        AssertThrow(Utilities::MPI::max(missing, comm) == 0,
                    ExcMessage("Solver/Implicit/Jacobian = Matrix free: a material has no analytic tangent "
                               "for the preconditioner; use Jacobian = Assembled"));
        std::vector<double> mass;
        if (newmark_inertia > 0)
          for (unsigned int k = 0; k < dim * cloud.n_owned(); ++k)
            mass.push_back(state.mass_density[k / dim] * cloud.volume[k / dim] * newmark_inertia);
        tangent->finish_diagonal(mass, block_inverse);
        return;
      }
    const bool analytic = !use_finite_differences && access.model.add_tangent(rows);
    // One block without an analytic tangent: finite differences for all
    // (the force differences see every block at once).
    if (Utilities::MPI::min(analytic ? 1u : 0u, comm) == 0)
      {
        if (!use_finite_differences)
          {
            use_finite_differences = true;
            access.record.warnings.push_back("a material has no analytic tangent: the implicit solver uses finite differences");
            tangent->begin(constrained_dofs);
          }
        double horizon = 0;
        for (const auto &b : access.model.blocks)
          horizon = std::max(horizon, b.horizon);
        tangent->add_finite_differences(state.displacement, state.force, [this] { access.model.compute_forces(false); }, fd_step,
                                        tangent->hops * horizon);
      }
    if (newmark_inertia > 0)
      {
        std::vector<double> mass(dim * cloud.n_owned());
        for (unsigned int k = 0; k < mass.size(); ++k)
          mass[k] = state.mass_density[k / dim] * cloud.volume[k / dim] * newmark_inertia;
        tangent->add_to_diagonal(mass);
      }
    tangent->finish();
    if (has_continuum)
      {
        TimerOutput::Scope t(timer, "implicit: coupled tangent");
        coupled_tangent->assemble(tangent->matrix);
        if (newmark_inertia > 0) // the PD points' mass went in through A
          {
            std::vector<double> mass(coupled_tangent->fe_dofs.size());
            for (unsigned int j = 0; j < mass.size(); ++j)
              mass[j] = continuum->mass.local_element(coupled_tangent->fe_dofs[j]) * newmark_inertia;
            coupled_tangent->add_to_fe_diagonal(mass);
          }
        rebuild_amg = true; // a new matrix object
        if (!symmetry_reported)
          {
            pcout << "  coupled tangent: " << coupled_tangent->matrix.n_nonzero_elements()
                  << " nonzeros; symmetry defect |x.Ky - y.Kx| / (|x| |y| |K|) = "
                  << sci(coupled_tangent->symmetry_defect(), 3)
                  << (force_blending ? residual_products() ? " (force blending, GMRES on products from the residual, "
                                                             "this matrix its AMG's)" :
                                                           " (force blending, GMRES)" :
                                       "")
                  << std::endl;
            symmetry_reported = true;
          }
      }
  }

  NewtonResult
  ImplicitSolver::solve_newton(const unsigned int step)
  {
    const unsigned int  n = n_unknowns();
    std::vector<double> R(n), du(n), u0(n);
    NewtonResult        result;
    double              forces = 0;
    check_pinned_loads(step);
    check_free_mode_loads(step);
    double              r      = residual(R, forces);
    rebuild_amg                = true; // a new solve builds its own hierarchy
    const double        r_start   = r;
    pcout << "  Newton 0: |R| = " << sci(r, 4) << std::endl;
    bool keep_tangent = false; // the last iteration contracted |R| enough
    for (unsigned int it = 1;; ++it)
      {
        const double target = std::max(implicit.tolerance * std::max(r_start, forces), implicit.absolute_tolerance);
        if (r <= target)
          break;
        if (it > implicit.max_newton)
          {
            result.failure = "Newton did not converge in step " + std::to_string(step) + " after " +
                             std::to_string(implicit.max_newton) + " iterations (|R| = " + sci(r) + ", wanted " +
                             sci(target) + "): take more (smaller) steps (Solver/Number of steps) or raise "
                             "Solver/Implicit/Maximum Newton iterations";
            break;
          }
        const bool kept = keep_tangent;
        if (!kept)
          assemble_tangent();
        unsigned int linear = 0;
        if (free_basis.empty())
          linear = solve_linear(R, du);
        else
          {
            // K is singular along the free motions: their pins are held at 0
            // (regular K, the same solution up to a motion: R has no part
            // along them), then the increment's motion is projected out.
            std::vector<double> R_held = R;
            for (const unsigned int j : mode_pins)
              R_held[j] = 0;
            linear = solve_linear(R_held, du);
            project_free_modes(du.data());
          }
        result.linear_iterations += linear;

        for (unsigned int k = 0; k < n; ++k)
          u0[k] = unknown(k);
        double       alpha = 1, r_new = 0;
        unsigned int cuts  = 0;
        for (;; ++cuts)
          {
            for (unsigned int k = 0; k < n; ++k)
              unknown(k) = u0[k] + alpha * du[k];
            r_new = residual(R, forces);
            if (!implicit.line_search || (std::isfinite(r_new) && r_new <= (1 - 1e-4 * alpha) * r) || cuts == 10)
              break;
            alpha /= 2;
          }
        if (kept && !(std::isfinite(r_new) && r_new < r))
          {
            // The kept tangent no longer leads down: the same iteration
            // again with a new one.
            for (unsigned int k = 0; k < n; ++k)
              unknown(k) = u0[k];
            r            = residual(R, forces);
            keep_tangent = false;
            pcout << "  Newton " << it << ": the kept tangent gave |R| = " << sci(r_new, 4)
                  << ": again with a new tangent" << std::endl;
            continue;
          }
        if (!std::isfinite(r_new))
          {
            result.failure = "the residual became non-finite in step " + std::to_string(step) +
                             ", Newton iteration " + std::to_string(it) + ": the step is too large";
            result.newton_iterations = it;
            break;
          }
        if (implicit.line_search && r_new > (1 - 1e-4 * alpha) * r)
          {
            // No descent along the Newton direction: at round-off, keep the
            // better state and stop; far from it, the tangent is wrong.
            const double scale = std::max(r_start, forces);
            if (r > 1e-6 * scale)
              {
                result.failure = "Newton stagnated in step " + std::to_string(step) + " at |R| = " + sci(r) + " (" +
                                 sci(r / scale) + " of the forces): the tangent does not match the force (try "
                                 "Solver/Implicit/Tangent = Finite differences)";
                result.newton_iterations = it;
                break;
              }
            for (unsigned int k = 0; k < n; ++k)
              unknown(k) = u0[k];
            r = residual(R, forces);
            pcout << "  Newton " << it << ": |R| = " << sci(r, 4) << " is at round-off (" << sci(r / scale, 3)
                  << " of the forces): accepted" << std::endl;
            result.newton_iterations = it;
            break;
          }
        pcout << "  Newton " << it << ": |R| = " << sci(r_new, 4) << " (" << linear_solver << " "
              << linear << " iterations" << (alpha < 1 ? ", step length " + sci(alpha, 3) : std::string())
              << (kept ? ", tangent kept" : "") << ")" << std::endl;
        keep_tangent = implicit.keep_tangent_contraction > 0 && alpha == 1 &&
                       r_new <= implicit.keep_tangent_contraction * r;
        r            = r_new;
        result.newton_iterations = it;
      }
    result.residual = r;
    return result;
  }

  bool
  ImplicitSolver::solve_step(const unsigned int step)
  {
    access.record.last_newton        = NewtonResult();
    access.record.last_damage_solves = 0;
    for (;;)
      {
        const NewtonResult solve = solve_newton(step);
        ++access.record.last_damage_solves;
        access.record.last_newton.newton_iterations += solve.newton_iterations;
        access.record.last_newton.linear_iterations += solve.linear_iterations;
        access.record.last_newton.residual = solve.residual;
        if (!solve.failure.empty())
          {
            access.record.last_newton.failure = solve.failure;
            return false;
          }
        if (access.model.broken.empty())
          return true;
        ForceModel::DamageSnapshot before;
        if (access.deck.solver.track_dissipation)
          access.model.save_damage(before);
        const std::size_t newly = access.model.break_bonds();
        if (newly == 0)
          return true;
        if (access.deck.solver.track_dissipation)
          access.record.dissipated_energy += access.model.released_energy(before);
        pcout << "  " << newly / 2 << (access.model.continuous_damage() ? " bonds took more damage" : " bonds broke")
              << ": solving the step again" << std::endl;
        if (access.record.last_damage_solves == implicit.max_damage_solves)
          {
            access.record.warnings.push_back("step " + std::to_string(step) + ": bonds still broke after " +
                               std::to_string(access.record.last_damage_solves) +
                               " solves (Solver/Implicit/Maximum damage solves)");
            return true;
          }
      }
  }

  ImplicitSolver::LoadPathState
  ImplicitSolver::load_path_state() const
  {
    const ConditionSet &conditions = access.conditions;
    LoadPathState       s;
    for (const auto &c : conditions.constraints)
      s.support.push_back(conditions.support_force(c));
    s.u.resize(state.size());
    for (unsigned int k = 0; k < state.size(); ++k)
      s.u[k] = state.u(k);
    if (conditions.has_loads())
      for (unsigned int k = 0; k < state.size(); ++k)
        s.load.push_back(conditions.load(k));
    return s;
  }

  double
  ImplicitSolver::load_path_work(const LoadPathState &start) const
  {
    // Trapezoidal sums of force x displacement increment: exact while the
    // forces change linearly over the step (a linear material, small strain).
    const ConditionSet &conditions = access.conditions;
    double              work       = 0;
    for (unsigned int c = 0; c < conditions.constraints.size(); ++c)
      {
        const unsigned int k = conditions.constraints[c].dof;
        work += 0.5 * (start.support[c] + conditions.support_force(conditions.constraints[c])) * (state.u(k) - start.u[k]);
      }
    // A load on a prescribed DoF is balanced by its support.
    if (!start.load.empty())
      state.for_each([&](const MechanicalState::DoF &d) {
        if (!conditions.prescribed[d.number])
          work += 0.5 * (start.load[d.number] + conditions.load(d.number)) * d.measure * (d.u - start.u[d.number]);
      });
    return Utilities::MPI::sum(work, comm);
  }

  // ------------------------------------------------- what both integrators share

  ImplicitSolver &
  ImplicitIntegrator::make_solver()
  {
    implicit_solver = std::make_unique<ImplicitSolver>(*access, access->deck.solver.implicit);
    implicit_solver->setup(need_supports());
    return *implicit_solver;
  }

  void
  ImplicitIntegrator::take_conversion()
  {
    access->conditions.take_constraint_state();
    make_solver();
  }

  double
  ImplicitIntegrator::accept(const double dt, const std::function<void(double)> &complete,
                             const ImplicitSolver::LoadPathState &load_start)
  {
    complete(dt);
    access->state.displacement.update_ghost_values();
    access->model.compute_forces(true);
    // The converged state is the sub-step's: its history is the next
    // one's start (Newton's iterations and line searches each
    // recomputed it from the last commit).
    access->model.commit_step();
    return implicit_solver->load_path_work(load_start);
  }

  NewtonResult
  ImplicitIntegrator::solve_again(const unsigned int step, const double t_end, const double dt,
                                  const std::function<void(double, double)> &prepare,
                                  const std::function<void(double)>         &complete)
  {
    RunRecord  &record = access->record;
    const auto  before = access->post.energies();
    const double released_before = record.dissipated_energy;
    const ImplicitSolver::LoadPathState load_start = implicit_solver->load_path_state();
    // The step again: prescribed displacements for the new points and
    // nodes, the prescribed velocities' displacements as integrated once.
    const std::vector<double> integrated = access->conditions.constraint_displacement;
    prepare(t_end, dt);
    access->conditions.keep_integrated(integrated);
    const bool converged = implicit_solver->solve_step(step);
    AssertThrow(converged, ExcMessage(record.last_newton.failure + " (the load step solved again after cells "
                                                                   "converted: Adaptivity)"));
    const double work  = accept(dt, complete, load_start);
    record.external_work += work;
    const auto   after = access->post.energies();
    // What the carried state gives up on its way to the new equilibrium
    // (beyond the energy the bonds that broke released) is the
    // conversion's, as its jump is. No inertia: strain energy only.
    const double relaxed = after.second + record.dissipated_energy - released_before - before.second - work;
    record.conversion_energy += relaxed;
    access->pcout << "  solved again at t = " << sci(t_end, 6) << " after the conversion: strain energy "
                  << sci(before.second, 6) << " -> " << sci(after.second, 6) << ", relaxation " << sci(relaxed, 3)
                  << " (counted with the conversion's jump)" << std::endl;
    return record.last_newton;
  }

  void
  ImplicitIntegrator::check_jacobian(const SolverParameters &solver, const bool has_continuum)
  {
    AssertThrow(!has_continuum || solver.implicit.jacobian == "Assembled",
                ExcMessage("Solver/Implicit/Jacobian: a scene with continuum blocks needs Assembled (the FE "
                           "stiffness joins the PD tangent in one matrix)"));
  }

  void
  ImplicitIntegrator::start_loop()
  {
    start = std::chrono::steady_clock::now();
  }

  double
  ImplicitIntegrator::loop_seconds() const
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  void
  ImplicitIntegrator::save(SubStepStart &into) const
  {
    const MechanicalState &state = access->state;
    into.u.resize(state.size());
    into.v.resize(state.size());
    for (unsigned int k = 0; k < state.size(); ++k)
      {
        into.u[k] = state.u(k);
        into.v[k] = state.v(k);
      }
    into.a   = state.acceleration;
    into.own = access->conditions.constraint_displacement;
    access->model.save_damage_state(into.damage);
    into.dissipated_energy = access->record.dissipated_energy;
  }

  void
  ImplicitIntegrator::restore(const SubStepStart &from) const
  {
    MechanicalState &state = access->state;
    for (unsigned int k = 0; k < state.size(); ++k)
      {
        state.u(k) = from.u[k];
        state.v(k) = from.v[k];
      }
    state.acceleration = from.a;
    // A prescribed velocity integrates its displacement step by step: the
    // cut sub-step starts from the integral at its start, not the failed one's end.
    access->conditions.constraint_displacement = from.own;
    state.displacement.update_ghost_values();
    access->model.restore_damage_state(from.damage);
    access->record.dissipated_energy = from.dissipated_energy;
  }

  void
  ImplicitIntegrator::advance(const unsigned int step, const double t_start, const double t_end, const double dt_step,
                              const unsigned int n_steps, const std::function<void(double, double)> &prepare,
                              const std::function<void(double)> &complete)
  {
    RunRecord                &record   = access->record;
    Postprocess              &post     = access->post;
    const ImplicitParameters &implicit = access->deck.solver.implicit;
    const double              span     = t_end - t_start;
    // "1/8 of the step", "0.75 of the step"
    const auto fraction = [](const double f) {
      if (f == 1)
        return std::string("the whole step");
      const long n = std::lround(1 / f);
      return (std::abs(n * f - 1) < 1e-9 ? "1/" + std::to_string(n) : sci(f, 6)) + " of the step";
    };
    NewtonResult                  sum;
    unsigned int                  solves = 0;
    const bool                    cut    = implicit.adaptive_steps;
    ImplicitSolver::LoadPathState load_start;
    bool                          retry  = false;   // the sub-step starts where a failed one started
    double                        t_last = t_start; // where the last sub-step started
    for (double t = t_start; t < t_end;)
      {
        // The last sub-step ends at t_end exactly: no sliver from round-off.
        double t_next = t + step_fraction * span;
        if (t_next >= t_end - 1e-9 * span)
          t_next = t_end;
        const double dt = t == t_start && t_next == t_end ? dt_step : t_next - t;
        if (t != t_start || t_next != t_end)
          access->pcout << "  sub-step to t = " << sci(t_next, 6) << ", " << fraction(dt / span) << std::endl;
        // After a cut the forces are the failed iterate's: the load path
        // starts from the state saved before it.
        if (!retry)
          {
            if (cut)
              save(sub_step_start);
            load_start = implicit_solver->load_path_state();
          }
        prepare(t_next, dt);
        const bool converged = implicit_solver->solve_step(step);
        sum.newton_iterations += record.last_newton.newton_iterations;
        sum.linear_iterations += record.last_newton.linear_iterations;
        sum.residual = record.last_newton.residual;
        solves += record.last_damage_solves;
        if (!converged)
          {
            const std::string &failure = record.last_newton.failure;
            AssertThrow(cut, ExcMessage(failure));
            AssertThrow(step_fraction / 2 >= implicit.min_step_fraction,
                        ExcMessage(failure + " (Solver/Implicit/Adaptive steps: the sub-step was " +
                                   fraction(step_fraction) + "; half of it is below Minimum step fraction = " +
                                   sci(implicit.min_step_fraction) + ")"));
            restore(sub_step_start);
            step_fraction /= 2;
            ++record.step_cuts;
            record.smallest_step_fraction = std::min(record.smallest_step_fraction, step_fraction);
            access->pcout << "  step cut to " << fraction(step_fraction) << ": " << failure << std::endl;
            retry = true;
            continue;
          }
        retry = false;
        const bool easy = record.last_newton.newton_iterations <= implicit.max_newton / 2;
        record.external_work += accept(dt, complete, load_start);
        t_last = t;
        t = t_next;
        if (easy && step_fraction < 1)
          step_fraction *= 2;
      }
    // Cells convert after the accepted step (Adaptivity). Without inertia
    // the step is solved again at its load on the new discretization: its
    // output is an equilibrium, bonds may break on in the converted cells
    // (and convert more), so that a crack runs as far in one load step as
    // it would in all-PD.
    if (access->adaptivity && step < n_steps && access->adaptivity->due(step))
      while (access->adaptivity->check(step, t_end, dt_step))
        {
          take_conversion();
          if (access->adaptivity->has_inertia())
            break;
          const NewtonResult again = solve_again(step, t_end, t_end - t_last, prepare, complete);
          sum.newton_iterations += again.newton_iterations;
          sum.linear_iterations += again.linear_iterations;
          solves += record.last_damage_solves;
        }
    record.last_newton        = sum;
    record.last_damage_solves = solves;
    total_newton += sum.newton_iterations;
    total_linear += sum.linear_iterations;
    total_solves += solves;
    if (post.output.is_output_step(step, n_steps))
      post.write_output(step, t_end, post.output.is_globals_step(step, n_steps),
                        post.output.is_field_step(step, n_steps));
    completed_step    = step;
    completed_time    = t_end;
    const bool signal = interrupt_signal(access->comm) != 0;
    checkpoint_step(step, t_end, signal);
    if (signal)
      access->stop_interrupted(step, t_end, n_steps, loop_seconds(), checkpoint_note);
  }

  void
  ImplicitIntegrator::save_state(CheckpointWriter &out) const
  {
    out.section("implicit");
    out.put(completed_step);
    out.put(completed_time);
    out.put(step_fraction);
    out.put(total_newton);
    out.put(total_linear);
    out.put(total_solves);
  }

  void
  ImplicitIntegrator::load_state(CheckpointReader &in)
  {
    in.section("implicit");
    in.get(completed_step);
    in.get(completed_time);
    in.get(step_fraction);
    in.get(total_newton);
    in.get(total_linear);
    in.get(total_solves);
  }

  void
  ImplicitIntegrator::restore_run(const unsigned int n_steps)
  {
    restore_checkpoint();
    // Cells converted before the checkpoint: the solver of the new numbering.
    if (access->adaptivity && access->adaptivity->any_converted())
      make_solver();
    AssertThrow(!access->last_stage || completed_step < n_steps,
                ExcMessage("--restart '" + access->restart + "': the checkpoint is of the run's last step (" +
                           std::to_string(completed_step) + "): nothing is left to run"));
    access->post.output.create_files(access->comm); // the checkpoint is accepted: now write
    first_step = completed_step + 1;
    // The next step's load work starts from the loads of the checkpoint's time.
    if (access->conditions.has_loads())
      access->conditions.evaluate_loads(completed_time);
  }

  void
  ImplicitIntegrator::check_stage()
  {
    if (need_supports())
      ImplicitSolver(*access, access->deck.solver.implicit).check_supports();
  }

  void
  ImplicitIntegrator::dry_run()
  {
    make_solver();
    access->pcout << "  tangent:           " << implicit_solver->describe_tangent() << "\n";
  }

  void
  ImplicitIntegrator::report_summary_speed(const double, const unsigned int) const
  {
    access->pcout << "  tangent:                " << implicit_solver->describe_tangent() << "\n";
    const RunRecord &record = access->record;
    if (record.step_cuts > 0)
      access->pcout << "  step cuts:              " << record.step_cuts << " (Solver/Implicit/Adaptive steps; the "
                    << "smallest sub-step 1/" << std::lround(1 / record.smallest_step_fraction) << " of a step)\n";
  }

  void
  ImplicitIntegrator::add_globals(std::vector<std::pair<std::string, double>> &row) const
  {
    const RunRecord    &record     = access->record;
    const ConditionSet &conditions = access->conditions;
    row.emplace_back("newton_iterations", record.last_newton.newton_iterations);
    row.emplace_back("linear_iterations", record.last_newton.linear_iterations);
    row.emplace_back("damage_solves", record.last_damage_solves);
    row.emplace_back("residual", record.last_newton.residual);
    // The force each prescribed condition's supports put on the body.
    std::vector<double> reaction(conditions.conditions.size(), 0.0);
    for (const auto &c : conditions.constraints)
      reaction[c.condition] += conditions.support_force(c);
    Utilities::MPI::sum(reaction, access->comm, reaction);
    for (unsigned int c = 0; c < conditions.conditions.size(); ++c)
      if (conditions.conditions[c].is_prescribed())
        row.emplace_back("reaction_" + conditions.conditions[c].name, reaction[c]);
  }
} // namespace perideal
