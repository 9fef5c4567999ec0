// The implicit solvers: Peridigm's QuasiStatic and implicit dynamics on
// deal.II and Trilinos.
//
// Quasistatic: load step k sets the prescribed displacements and body forces
// at pseudo-time t_k and solves R(u) = V (f(u) + b) = 0 on the free degrees of
// freedom. Newmark-beta: step k solves R(u) = V (f(u) + b) - M a(u) = 0 with
// M = rho V (diagonal: a peridynamic point's consistent mass is its own) and
// a(u) = (u - u_pred) / (beta dt^2), u_pred = u + dt v + dt^2/2 (1 - 2 beta) a.
// Both by Newton's method: K du = R with K = -dR/du (solver/tangent.h; plus
// M / (beta dt^2) for Newmark), then a backtracking line search on |R|. Bonds
// do not break inside Newton (the residual must be smooth); after a converged
// solve the damage models run, and the step is solved again while bonds break
// (at most "Maximum damage solves" times).

#include <perideal/base/interrupt.h>
#include <perideal/solver/coupled_tangent.h>
#include <perideal/solver/implicit.h>
#include <perideal/solver/rigid_modes.h>
#include <perideal/solver/simulation.h>

#include <deal.II/base/mpi.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_vector.h>

#include <Epetra_MultiVector.h>
#include <Teuchos_ParameterList.hpp>

#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    std::string
    sci(const double v, const unsigned int digits = 4)
    {
      std::ostringstream o;
      o << std::setprecision(digits) << v;
      return o.str();
    }
  } // namespace

  void
  ImplicitParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Tolerance", "1e-8", Patterns::Double(0),
                      "Newton stops when |R| <= Tolerance x max(|R| at the start of the solve, |F|): R "
                      "the residual on the free degrees of freedom (V(f + b), minus M a for Newmark), F "
                      "= V(f + b) on all of them (the forces in the body, reactions included).");
    prm.declare_entry("Absolute tolerance", "0", Patterns::Double(0),
                      "Newton also stops when |R| <= this (force units); 0: off.");
    prm.declare_entry("Maximum Newton iterations", "25", Patterns::Integer(1),
                      "A solve that has not converged after this many iterations stops the run with an error.");
    prm.declare_entry("Line search", "true", Patterns::Bool(),
                      "Backtracking line search on |R|: halve the Newton step (at most 10 times) "
                      "until |R| decreases.");
    prm.declare_entry("Linear solver", "CG", Patterns::Selection("CG|GMRES"),
                      "Krylov solver for K du = R. K is symmetric for PMB and LPS: CG. GMRES for "
                      "models whose tangent is not symmetric.");
    prm.declare_entry("Preconditioner", "AMG", Patterns::Selection("AMG|Jacobi"),
                      "AMG: Trilinos ML smoothed aggregation with the six rigid-body modes as near "
                      "null space; Jacobi: the diagonal (for comparison).");
    prm.declare_entry("AMG aggregation threshold", "0", Patterns::Double(0, 1),
                      "ML drops the couplings weaker than this (relative to the diagonal) before it "
                      "aggregates. 0: automatic, 1e-4 (deal.II's default) for a tangent that couples "
                      "a point to its family only (PMB), 0.005 for one that couples it to its "
                      "neighbors' families (LPS): with hundreds of couplings per row, LPS needs the "
                      "weak ones dropped (12^3 cube: 27 CG iterations with 1e-4, 13 with 0.005), "
                      "but not too many (dog-bone of doc/examples/dogbone_tensile: 29 with 0.005, "
                      "77 with 0.02, 200 with 0.1), while PMB's counts grow with the mesh at 0.1 "
                      "(10^3 to 30^3 points: 8 to 34) and stay nearly constant at 1e-4 (13 to 18).");
    prm.declare_entry("Linear tolerance", "1e-10", Patterns::Double(0),
                      "The Krylov solver stops at |K du - R| <= this x |R|. Newton converges "
                      "quadratically only while this is far below the Newton tolerance.");
    prm.declare_entry("Maximum linear iterations", "1000", Patterns::Integer(1),
                      "More stops the run with an error.");
    prm.declare_entry("Tangent", "Analytic", Patterns::Selection("Analytic|Finite differences"),
                      "Analytic: each material's own tangent (PMB, LPS); a material without one "
                      "falls back to finite differences. Finite differences: central differences "
                      "of the force for every material (6 force evaluations per colour; see the "
                      "set-up report for the number of colours).");
    prm.declare_entry("Jacobian", "Assembled", Patterns::Selection("Assembled|Matrix free"),
                      "Assembled: the tangent in a Trilinos sparse matrix, Krylov solver and "
                      "preconditioner as chosen above. Matrix free: Jacobian-free Newton-Krylov for "
                      "scenes whose matrix does not fit: the Linear solver (CG, or GMRES(50)) on finite "
                      "differences of the residual (K v ~ -(R(u + e v) - R(u))/e, one force evaluation "
                      "per iteration), "
                      "preconditioned by the inverse 3x3 diagonal blocks of the analytic tangent (9 "
                      "numbers per point instead of the matrix). Needs materials with an analytic tangent.");
    prm.declare_entry("Maximum damage solves", "20", Patterns::Integer(1),
                      "After a converged solve the damage models break bonds; the step is solved "
                      "again while bonds break, at most this many times (then a warning).");
    prm.declare_entry("Newmark beta", "0.25", Patterns::Double(0, 0.5),
                      "Newmark's beta; 1/4 with gamma 1/2 is the trapezoidal rule: unconditionally "
                      "stable, second order, no numerical damping.");
    prm.declare_entry("Newmark gamma", "0.5", Patterns::Double(0, 1),
                      "Newmark's gamma; above 1/2 damps high frequencies (unconditionally stable for "
                      "gamma >= 1/2 and beta >= (gamma + 1/2)^2 / 4).");
  }

  void
  ImplicitParameters::parse_parameters(ParameterHandler &prm)
  {
    tolerance          = prm.get_double("Tolerance");
    absolute_tolerance = prm.get_double("Absolute tolerance");
    max_newton         = prm.get_integer("Maximum Newton iterations");
    line_search        = prm.get_bool("Line search");
    linear_solver      = prm.get("Linear solver");
    preconditioner     = prm.get("Preconditioner");
    aggregation_threshold = prm.get_double("AMG aggregation threshold");
    linear_tolerance   = prm.get_double("Linear tolerance");
    max_linear         = prm.get_integer("Maximum linear iterations");
    tangent            = prm.get("Tangent");
    jacobian           = prm.get("Jacobian");
    AssertThrow(jacobian == "Assembled" || tangent == "Analytic",
                ExcMessage("Solver/Implicit/Jacobian = Matrix free needs Tangent = Analytic (its "
                           "preconditioner is the analytic tangent's diagonal)"));
    max_damage_solves  = prm.get_integer("Maximum damage solves");
    beta               = prm.get_double("Newmark beta");
    gamma              = prm.get_double("Newmark gamma");
    AssertThrow(tolerance > 0 || absolute_tolerance > 0,
                ExcMessage("Solver/Implicit/Tolerance and Absolute tolerance are both 0: Newton would never stop"));
    // Both are relative: at 1 or more Newton accepts the initial guess (no
    // solve, exit 0 with the loads unbalanced), and the Krylov solver returns
    // du = 0 (Newton then "stagnates", blamed on the tangent).
    AssertThrow(tolerance < 1,
                ExcMessage("Solver/Implicit/Tolerance must be below 1, got " + Utilities::to_string(tolerance) +
                           ": it is relative to the forces, and at 1 or more Newton accepts the initial guess "
                           "without solving (e.g. 1e-8; Absolute tolerance is the one in force units)"));
    AssertThrow(linear_tolerance < 1,
                ExcMessage("Solver/Implicit/Linear tolerance must be below 1, got " +
                           Utilities::to_string(linear_tolerance) +
                           ": it is relative to |R|, and at 1 or more the Krylov solver returns a zero "
                           "Newton step (e.g. 1e-10)"));
    // Below 1/2 Newmark's numerical damping is negative: the energy grows
    // every step, whatever the step (a run of box.prm with gamma = 0: 18%
    // energy error in two steps, exit 0).
    AssertThrow(gamma >= 0.5,
                ExcMessage("Solver/Implicit/Newmark gamma must be at least 0.5, got " + Utilities::to_string(gamma) +
                           ": below it the scheme adds energy every step (unstable for any time step); "
                           "0.5 conserves energy, more damps it"));
    AssertThrow(beta > 0, ExcMessage("Solver/Implicit/Newmark beta must be positive (beta = 0 is the explicit "
                                     "central difference: use Solver/Type = Verlet)"));
  }

  // ------------------------------------------------------------------ set-up

  void
  Simulation::setup_implicit(const bool need_supports)
  {
    unsigned int hops = 1;
    for (const auto &b : blocks)
      hops = std::max(hops, b.material->coupling_hops());

    // Which local degrees of freedom are prescribed (ghosts from their owners).
    const unsigned int n_owned = cloud.n_owned();
    {
      VectorType flags(cloud.vector_partitioner);
      for (const auto &c : constraints)
        flags.local_element(dim * c.point + c.component) = 1;
      flags.update_ghost_values();
      constrained_dofs.assign(dim * cloud.n_local(), 0);
      for (unsigned int k = 0; k < dim * cloud.n_local(); ++k)
        constrained_dofs[k] = flags.local_element(k) != 0;
    }

    // The unknowns (with continuum blocks: the free DoFs of real points and
    // FE nodes, coupled_tangent.h; without: every owned PD DoF, prescribed
    // ones with identity rows) and the prescribed entries, by position and
    // component: the rigid-body modes about the centroid are the AMG's near
    // null space and the motions some condition must remove.
    std::vector<std::pair<Point<dim>, unsigned int>> unknowns, prescribed;
    std::vector<unsigned int>                        pd_free, fe_free;
    if (has_continuum)
      {
        for (unsigned int k = 0; k < dim * n_owned; ++k)
          if (!constrained_dofs[k] && !is_virtual(k / dim))
            pd_free.push_back(k);
        const std::vector<std::uint8_t> fe_prescribed = fe_prescribed_flags();
        for (const auto &c : node_constraints)
          prescribed.emplace_back(continuum->nodes[c.node].x, continuum->nodes[c.node].component);
        for (const unsigned int l : continuum->free)
          if (!fe_prescribed[l])
            fe_free.push_back(l);
        std::vector<unsigned int> node_of(continuum->F.locally_owned_size(), 0);
        for (unsigned int k = 0; k < continuum->nodes.size(); ++k)
          node_of[continuum->nodes[k].local] = k;
        for (const unsigned int k : pd_free)
          unknowns.emplace_back(cloud.position(k / dim), k % dim);
        for (const unsigned int l : fe_free)
          unknowns.emplace_back(continuum->nodes[node_of[l]].x, continuum->nodes[node_of[l]].component);
      }
    else
      for (unsigned int k = 0; k < dim * n_owned; ++k)
        unknowns.emplace_back(cloud.position(k / dim), k % dim);
    for (const auto &c : constraints)
      prescribed.emplace_back(cloud.position(c.point), c.component);

    std::array<double, dim> centre{{0, 0, 0}};
    {
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
    }
    const unsigned int n = unknowns.size();
    rigid_modes.assign(6 * n, 0.0);
    double extent = 0;
    for (unsigned int k = 0; k < n; ++k)
      {
        const auto  &[p, c] = unknowns[k];
        const double x = p[0] - centre[0], y = p[1] - centre[1], z = p[2] - centre[2];
        extent = std::max({extent, std::abs(x), std::abs(y), std::abs(z)});
        for (unsigned int mode = 0; mode < 6; ++mode)
          rigid_modes[mode * n + k] = rigid_mode_value(mode, c, x, y, z);
      }
    extent = Utilities::MPI::max(extent, comm);
    // A motion is removed if a prescribed entry moves with it; a hinge or
    // a single held point leaves combinations of the coordinate modes free.
    std::string free_modes;
    for (const auto &mode : free_rigid_modes(prescribed, centre, extent, comm))
      free_modes += (free_modes.empty() ? "" : ", ") + mode;
    AssertThrow(!need_supports || free_modes.empty(),
                ExcMessage("the quasistatic problem is singular: no boundary condition removes the rigid-body "
                           "motion(s) " + free_modes + ". Prescribe displacements (Type = Prescribed "
                           "displacement) on regions that hold the body in place"));

    {
      TimerOutput::Scope t(timer, "implicit: sparsity");
      tangent = std::make_unique<Tangent>();
      if (implicit.jacobian == "Matrix free")
        tangent->reinit_diagonal(cloud, hops, comm);
      else
        tangent->reinit(cloud, bonds, hops, comm);
      if (has_continuum)
        {
          coupled_tangent = std::make_unique<CoupledTangent>();
          coupled_tangent->reinit(pd_free, fe_free, virtual_points, continuum->interpolation(), tangent->owned,
                                  continuum->vector_partitioner(), continuum->stiffness(), comm);
          symmetry_reported = false;
        }
    }
    use_finite_differences = implicit.tangent == "Finite differences";
    fd_step                = std::numeric_limits<double>::max();
    for (unsigned int i = 0; i < n_owned; ++i)
      fd_step = std::min(fd_step, 1e-6 * std::cbrt(cloud.volume[i]));
    fd_step = Utilities::MPI::min(fd_step, comm);
  }

  // --------------------------------------------------------------- the solve

  double
  Simulation::residual(std::vector<double> &R, double &force_norm)
  {
    TimerOutput::Scope t(timer, "implicit: residual");
    if (has_continuum)
      {
        if (continuum->hanging.n_constraints() > 0)
          continuum->hanging.distribute(continuum->U);
        update_virtual_points();
      }
    displacement.update_ghost_values();
    compute_forces(false);
    double free = 0, all = 0;
    if (has_continuum)
      {
        // The free DoFs (coupled_tangent.h): V f at real points, the FE nodal
        // force Pi^T (V f) - K U + load; the force scale over every real point
        // and FE node, supports included.
        const std::vector<unsigned int> &pd = coupled_tangent->pd_dofs, &fe = coupled_tangent->fe_dofs;
        for (unsigned int j = 0; j < pd.size(); ++j)
          {
            const unsigned int k = pd[j];
            R[j]                 = cloud.volume[k / dim] * force.local_element(k);
            if (newmark_inertia > 0)
              R[j] -= mass_density[k / dim] * cloud.volume[k / dim] * newmark_inertia *
                      (displacement.local_element(k) - u_predicted[k]);
          }
        for (unsigned int j = 0; j < fe.size(); ++j)
          {
            const unsigned int l = fe[j];
            R[pd.size() + j]     = continuum->F.local_element(l);
            if (newmark_inertia > 0)
              R[pd.size() + j] -= continuum->mass.local_element(l) * newmark_inertia *
                                  (continuum->U.local_element(l) - fe_u_predicted[l]);
          }
        for (const double r : R)
          free += r * r;
        for (unsigned int k = 0; k < dim * cloud.n_owned(); ++k)
          if (!is_virtual(k / dim))
            all += std::pow(cloud.volume[k / dim] * force.local_element(k), 2);
        for (const unsigned int l : continuum->free)
          all += std::pow(continuum->F.local_element(l), 2);
      }
    else
      for (unsigned int k = 0; k < dim * cloud.n_owned(); ++k)
        {
          double r = cloud.volume[k / dim] * force.local_element(k);
          if (newmark_inertia > 0)
            r -= mass_density[k / dim] * cloud.volume[k / dim] * newmark_inertia *
                 (displacement.local_element(k) - u_predicted[k]);
          R[k] = constrained_dofs[k] ? 0 : r;
          free += R[k] * R[k];
          const double F = cloud.volume[k / dim] * force.local_element(k);
          all += F * F;
        }
    double sums[2] = {free, all};
    Utilities::MPI::sum(ArrayView<const double>(sums, 2), comm, ArrayView<double>(sums, 2));
    force_norm = std::sqrt(sums[1]);
    return std::sqrt(sums[0]);
  }

  unsigned int
  Simulation::n_unknowns() const
  {
    return has_continuum ? coupled_tangent->pd_dofs.size() + coupled_tangent->fe_dofs.size() : dim * cloud.n_owned();
  }

  double &
  Simulation::unknown(const unsigned int j)
  {
    if (!has_continuum)
      return displacement.local_element(j);
    const std::vector<unsigned int> &pd = coupled_tangent->pd_dofs;
    return j < pd.size() ? displacement.local_element(pd[j]) :
                           continuum->U.local_element(coupled_tangent->fe_dofs[j - pd.size()]);
  }

  void
  Simulation::assemble_tangent()
  {
    TimerOutput::Scope t(timer, "implicit: tangent");
    TangentRows       &rows = tangent->begin(constrained_dofs);
    ModelState state{cloud, bonds, broken.empty() ? nullptr : broken.data(), displacement.begin(),
                     force.begin(), nullptr, *fields};
    if (implicit.jacobian == "Matrix free")
      {
        unsigned int missing = 0;
        for (unsigned int k = 0; k < blocks.size(); ++k)
          if (!blocks[k].points.empty() && !blocks[k].material->add_tangent(state, blocks[k].points, rows))
            missing = 1;
        AssertThrow(Utilities::MPI::max(missing, comm) == 0,
                    ExcMessage("Solver/Implicit/Jacobian = Matrix free: a material has no analytic tangent "
                               "for the preconditioner; use Jacobian = Assembled"));
        std::vector<double> mass;
        if (newmark_inertia > 0)
          for (unsigned int k = 0; k < dim * cloud.n_owned(); ++k)
            mass.push_back(mass_density[k / dim] * cloud.volume[k / dim] * newmark_inertia);
        tangent->finish_diagonal(mass, block_inverse);
        return;
      }
    bool analytic = !use_finite_differences;
    for (unsigned int k = 0; k < blocks.size() && analytic; ++k)
      if (!blocks[k].points.empty() && !blocks[k].material->add_tangent(state, blocks[k].points, rows))
        analytic = false;
    // One block without an analytic tangent: finite differences for all
    // (the force differences see every block at once).
    if (Utilities::MPI::min(analytic ? 1u : 0u, comm) == 0)
      {
        if (!use_finite_differences)
          {
            use_finite_differences = true;
            warnings.push_back("a material has no analytic tangent: the quasistatic solver uses finite differences");
            tangent->begin(constrained_dofs);
          }
        double horizon = 0;
        for (const auto &b : blocks)
          horizon = std::max(horizon, b.horizon);
        tangent->add_finite_differences(displacement, force, [this] { compute_forces(false); }, fd_step,
                                        tangent->hops * horizon);
      }
    if (newmark_inertia > 0)
      {
        std::vector<double> mass(dim * cloud.n_owned());
        for (unsigned int k = 0; k < mass.size(); ++k)
          mass[k] = mass_density[k / dim] * cloud.volume[k / dim] * newmark_inertia;
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
                  << sci(coupled_tangent->symmetry_defect(), 3) << std::endl;
            symmetry_reported = true;
          }
      }
  }

  unsigned int
  Simulation::solve_linear(const std::vector<double> &R, std::vector<double> &du)
  {
    if (implicit.jacobian == "Matrix free")
      return solve_matrix_free(R, du);
    TimerOutput::Scope            t(timer, "implicit: linear solve");
    const IndexSet               &owned  = has_continuum ? coupled_tangent->owned : tangent->owned;
    const TrilinosWrappers::SparseMatrix &matrix = has_continuum ? coupled_tangent->matrix : tangent->matrix;
    TrilinosWrappers::MPI::Vector rhs(owned, comm), x(owned, comm);
    const types::global_dof_index first = owned.n_elements() ? *owned.begin() : 0;
    for (unsigned int k = 0; k < R.size(); ++k)
      rhs[first + k] = R[k];
    rhs.compress(VectorOperation::insert);

    SolverControl control(implicit.max_linear, implicit.linear_tolerance * rhs.l2_norm(), false, false);
    // The AMG hierarchy of the first Newton iteration of a solve serves its
    // later iterations (the tangent changes little), until the Krylov
    // iterations grow past twice those of the iteration that built it.
    const bool reuse = implicit.preconditioner == "AMG" && amg && !rebuild_amg;
    std::unique_ptr<TrilinosWrappers::PreconditionBase> jacobi_preconditioner;
    if (reuse)
      {}
    else if (implicit.preconditioner == "AMG")
      {
        TrilinosWrappers::PreconditionAMG::AdditionalData data;
        data.elliptic              = true;
        data.higher_order_elements = false;
        data.smoother_sweeps       = 2;
        data.aggregation_threshold = implicit.aggregation_threshold > 0 ? implicit.aggregation_threshold :
                                     tangent->hops == 2                 ? 0.005 :
                                                                          1e-4;
        Teuchos::ParameterList              list;
        std::unique_ptr<Epetra_MultiVector> unused;
        data.set_parameters(list, unused, matrix);
        list.set("null space: type", "pre-computed");
        list.set("null space: dimension", 6);
        list.set("null space: vectors", rigid_modes.data());
        amg = std::make_unique<TrilinosWrappers::PreconditionAMG>();
        amg->initialize(matrix, list);
      }
    else
      {
        auto jacobi = std::make_unique<TrilinosWrappers::PreconditionJacobi>();
        jacobi->initialize(matrix);
        jacobi_preconditioner = std::move(jacobi);
      }
    const TrilinosWrappers::PreconditionBase &preconditioner =
      jacobi_preconditioner ? *jacobi_preconditioner : static_cast<const TrilinosWrappers::PreconditionBase &>(*amg);
    try
      {
        if (implicit.linear_solver == "CG")
          SolverCG<TrilinosWrappers::MPI::Vector>(control).solve(matrix, x, rhs, preconditioner);
        else
          SolverGMRES<TrilinosWrappers::MPI::Vector>(control).solve(matrix, x, rhs, preconditioner);
      }
    catch (const SolverControl::NoConvergence &e)
      {
        AssertThrow(false,
                    ExcMessage("the linear solver (" + implicit.linear_solver + ", " + implicit.preconditioner +
                               ") did not converge in " + std::to_string(e.last_step) + " iterations (residual " +
                               sci(e.last_residual) + ", wanted " + sci(control.tolerance()) +
                               "): raise Solver/Implicit/Maximum linear iterations, or the tangent is "
                               "singular (a part of the body held by no condition, e.g. a fragment)"));
      }
    if (!reuse)
      amg_iterations = control.last_step();
    rebuild_amg = reuse && control.last_step() > 2 * amg_iterations + 5;
    for (unsigned int k = 0; k < du.size(); ++k)
      du[k] = x[first + k];
    return control.last_step();
  }

  namespace
  {
    /// An operator from a function, for deal.II's solvers.
    struct FunctionOperator
    {
      std::function<void(VectorType &, const VectorType &)> apply;
      void
      vmult(VectorType &dst, const VectorType &src) const
      {
        apply(dst, src);
      }
    };
  } // namespace

  unsigned int
  Simulation::solve_matrix_free(const std::vector<double> &R, std::vector<double> &du)
  {
    TimerOutput::Scope  t(timer, "implicit: linear solve");
    const unsigned int  n = R.size();
    VectorType          rhs(tangent->owned, comm), x(tangent->owned, comm);
    std::vector<double> u0(n), R_plus(n);
    for (unsigned int k = 0; k < n; ++k)
      {
        rhs.local_element(k) = R[k];
        u0[k]                = displacement.local_element(k);
      }
    double u_norm = 0;
    for (const double v : u0)
      u_norm += v * v;
    u_norm = std::sqrt(Utilities::MPI::sum(u_norm, comm));

    // K v = -dR/du v by a forward difference of the residual; identity rows
    // at the prescribed DoFs.
    const FunctionOperator K{[&](VectorType &dst, const VectorType &src) {
      const double v_norm = src.l2_norm();
      if (v_norm == 0)
        {
          dst = 0;
          return;
        }
      const double e = 1e-8 * (1 + u_norm) / v_norm;
      for (unsigned int k = 0; k < n; ++k)
        displacement.local_element(k) = u0[k] + e * src.local_element(k);
      double forces = 0;
      residual(R_plus, forces);
      for (unsigned int k = 0; k < n; ++k)
        dst.local_element(k) = constrained_dofs[k] ? src.local_element(k) : -(R_plus[k] - R[k]) / e;
    }};
    const FunctionOperator P{[&](VectorType &dst, const VectorType &src) {
      for (unsigned int i = 0; i < n / dim; ++i)
        for (unsigned int r = 0; r < dim; ++r)
          {
            double s = 0;
            for (unsigned int c = 0; c < dim; ++c)
              s += block_inverse[9 * i + dim * r + c] * src.local_element(dim * i + c);
            dst.local_element(dim * i + r) = s;
          }
    }};
    SolverControl control(implicit.max_linear, implicit.linear_tolerance * rhs.l2_norm(), false, false);
    try
      {
        // CG needs a symmetric operator: the tangent of PMB and LPS is, and its
        // finite difference is up to O(e).
        if (implicit.linear_solver == "CG")
          SolverCG<VectorType>(control).solve(K, x, rhs, P);
        else
          SolverGMRES<VectorType>(control, SolverGMRES<VectorType>::AdditionalData(50, true)).solve(K, x, rhs, P);
      }
    catch (const SolverControl::NoConvergence &e)
      {
        AssertThrow(false,
                    ExcMessage("the matrix-free linear solver (" + implicit.linear_solver +
                               ", block Jacobi) did not converge in " +
                               std::to_string(e.last_step) + " iterations (residual " + sci(e.last_residual) +
                               ", wanted " + sci(control.tolerance()) +
                               "): raise Solver/Implicit/Maximum linear iterations, or use Jacobian = Assembled "
                               "with AMG"));
      }
    for (unsigned int k = 0; k < n; ++k)
      {
        du[k]                         = x.local_element(k);
        displacement.local_element(k) = u0[k];
      }
    return control.last_step();
  }

  std::string
  Simulation::describe_tangent() const
  {
    const double bytes = Utilities::MPI::sum(double(tangent->memory_consumption()), comm);
    if (implicit.jacobian == "Matrix free")
      return "matrix free (" + implicit.linear_solver + ", block Jacobi from the analytic diagonal; " + sci(bytes / 1048576.0, 4) + " MiB)";
    if (has_continuum)
      return std::string(use_finite_differences ? "by finite differences" : "analytic") + ", PD part " +
             std::to_string(tangent->matrix.n_nonzero_elements()) + " nonzeros, coupled T^T A T + K_FE on " +
             std::to_string(coupled_tangent->owned.size()) + " free DoFs (" +
             sci(Utilities::MPI::sum(double(coupled_tangent->memory_consumption()), comm) / 1048576.0 +
                   bytes / 1048576.0, 4) +
             " MiB), " + implicit.linear_solver + " with " + implicit.preconditioner;
    return std::string(use_finite_differences ? "by finite differences" : "analytic") + ", " +
           std::to_string(tangent->matrix.n_nonzero_elements()) + " nonzeros (" + sci(bytes / 1048576.0, 4) +
           " MiB), " + implicit.linear_solver + " with " + implicit.preconditioner;
  }

  Simulation::NewtonResult
  Simulation::solve_newton(const unsigned int step)
  {
    const unsigned int  n = n_unknowns();
    std::vector<double> R(n), du(n), u0(n);
    NewtonResult        result;
    double              forces = 0;
    double              r      = residual(R, forces);
    rebuild_amg                = true; // a new solve builds its own hierarchy
    const double        r_start   = r;
    pcout << "  Newton 0: |R| = " << sci(r, 4) << std::endl;
    for (unsigned int it = 1;; ++it)
      {
        const double target = std::max(implicit.tolerance * std::max(r_start, forces), implicit.absolute_tolerance);
        if (r <= target)
          break;
        AssertThrow(it <= implicit.max_newton,
                    ExcMessage("Newton did not converge in step " + std::to_string(step) + " after " +
                               std::to_string(implicit.max_newton) + " iterations (|R| = " + sci(r) +
                               ", wanted " + sci(target) + "): take more (smaller) steps (Solver/Number of steps) "
                               "or raise Solver/Implicit/Maximum Newton iterations"));
        assemble_tangent();
        const unsigned int linear = solve_linear(R, du);
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
        AssertThrow(std::isfinite(r_new),
                    ExcMessage("the residual became non-finite in step " + std::to_string(step) +
                               ", Newton iteration " + std::to_string(it) + ": the step is too large"));
        if (implicit.line_search && r_new > (1 - 1e-4 * alpha) * r)
          {
            // No descent along the Newton direction: at round-off, keep the
            // better state and stop; far from it, the tangent is wrong.
            const double scale = std::max(r_start, forces);
            AssertThrow(r <= 1e-6 * scale,
                        ExcMessage("Newton stagnated in step " + std::to_string(step) + " at |R| = " + sci(r) +
                                   " (" + sci(r / scale) + " of the forces): the tangent does not match the "
                                   "force (try Solver/Implicit/Tangent = Finite differences)"));
            for (unsigned int k = 0; k < n; ++k)
              unknown(k) = u0[k];
            r = residual(R, forces);
            pcout << "  Newton " << it << ": |R| = " << sci(r, 4) << " is at round-off (" << sci(r / scale, 3)
                  << " of the forces): accepted" << std::endl;
            result.newton_iterations = it;
            break;
          }
        pcout << "  Newton " << it << ": |R| = " << sci(r_new, 4) << " (" << implicit.linear_solver << " "
              << linear << " iterations" << (alpha < 1 ? ", step length " + sci(alpha, 3) : std::string()) << ")"
              << std::endl;
        r = r_new;
        result.newton_iterations = it;
      }
    result.residual = r;
    return result;
  }

  void
  Simulation::run_quasistatic()
  {
    const unsigned int n_steps = requested_steps;
    const double       t0      = initial_time;
    const double       t1      = final_time > initial_time ? final_time : initial_time + 1;
    const double       dt_load = (t1 - t0) / n_steps;
    dt                         = dt_load;
    output.initialize(comm);
    apply_initial_conditions();
    breaking_allowed = false;
    setup_implicit(true);
    stop_if_interrupted_in_setup();
    pcout << "Quasistatic: " << n_steps << " load steps from t = " << t0 << " to " << t1 << "; tangent "
          << describe_tangent() << std::endl;

    evaluate_initial_state();
    record_initial_state(n_steps, t0);

    const auto   start          = std::chrono::steady_clock::now();
    unsigned int total_newton   = 0, total_linear = 0, total_solves = 0;
    unsigned int step           = 1;
    for (; step <= n_steps; ++step)
      {
        const double time = t0 + step * dt_load;
        pcout << "Load step " << step << "/" << n_steps << ", t = " << sci(time, 6) << std::endl;
        const LoadPathState step_start = load_path_state();
        apply_prescribed(time, dt_load);
        // No motion between load steps (apply_prescribed sets the supports'
        // rate), so no kinetic energy.
        velocity = 0;
        if (has_continuum)
          continuum->V = 0;
        if (loads_depend_on_time)
          evaluate_loads(time);
        check_condition_values(first_nonfinite_condition(time), time);
        solve_step(step);
        total_newton += last_newton.newton_iterations;
        total_linear += last_newton.linear_iterations;
        total_solves += last_damage_solves;
        displacement.update_ghost_values();
        compute_forces(true);
        external_work += load_path_work(step_start);
        if (output.is_output_step(step, n_steps))
          write_output(step, time, output.is_globals_step(step, n_steps), output.is_field_step(step, n_steps));
        // SIGTERM, SIGINT: stop after the load step (one reduction per step).
        if (interrupt_signal(comm) != 0)
          stop_interrupted(step, time, n_steps,
                           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // The energy balance needs the final strain energy.
    if (!output.is_output_step(n_steps, n_steps))
      global_quantities(n_steps, t1);
    pcout << "\nQuasistatic: " << n_steps << " load steps, " << total_solves << " solves, " << total_newton
          << " Newton iterations, " << total_linear << " " << implicit.linear_solver << " iterations in "
          << sci(seconds, 4) << " s" << std::endl;
    print_summary(seconds, n_steps);
  }

  void
  Simulation::solve_step(const unsigned int step)
  {
    last_newton        = NewtonResult();
    last_damage_solves = 0;
    for (;;)
      {
        const NewtonResult solve = solve_newton(step);
        ++last_damage_solves;
        last_newton.newton_iterations += solve.newton_iterations;
        last_newton.linear_iterations += solve.linear_iterations;
        last_newton.residual = solve.residual;
        if (broken.empty())
          return;
        std::vector<std::uint8_t> broken_before;
        if (track_dissipation)
          broken_before = broken;
        const std::size_t newly = break_bonds();
        if (newly == 0)
          return;
        if (track_dissipation)
          dissipated_energy += released_energy(broken_before);
        pcout << "  " << newly / 2 << " bonds broke: solving the step again" << std::endl;
        if (last_damage_solves == implicit.max_damage_solves)
          {
            warnings.push_back("step " + std::to_string(step) + ": bonds still broke after " +
                               std::to_string(last_damage_solves) +
                               " solves (Solver/Implicit/Maximum damage solves)");
            return;
          }
      }
  }

  void
  Simulation::run_newmark()
  {
    const unsigned int n_steps = requested_steps;
    const double       t0 = initial_time, beta = implicit.beta, gamma = implicit.gamma;
    dt                    = (final_time - initial_time) / n_steps;
    output.initialize(comm);
    apply_initial_conditions();
    breaking_allowed = false;
    setup_implicit(false);
    stop_if_interrupted_in_setup();
    const unsigned int n = dim * cloud.n_owned();
    double *const      u = displacement.begin();
    double *const      v = velocity.begin();

    // The FE nodes of continuum blocks: the same steps over the owned DoFs
    // that carry equations (hanging ones follow their masters).
    const std::vector<unsigned int> no_dofs;
    const std::vector<unsigned int> &fe_dofs = has_continuum ? continuum->free : no_dofs;
    double *const U = has_continuum ? continuum->U.begin() : nullptr;
    double *const V = has_continuum ? continuum->V.begin() : nullptr;
    std::vector<double> fe_v_predicted(fe_dofs.size());
    if (has_continuum)
      {
        fe_u_predicted.assign(continuum->U.locally_owned_size(), 0.0);
        fe_acceleration.assign(continuum->U.locally_owned_size(), 0.0);
      }

    // The initial acceleration from the equation of motion (virtual points
    // have no mass: they follow the FE field).
    evaluate_initial_state();
    acceleration.resize(n);
    for (unsigned int k = 0; k < n; ++k)
      acceleration[k] = mass_density[k / dim] > 0 ? force.local_element(k) / mass_density[k / dim] : 0.0;
    for (const unsigned int l : fe_dofs)
      fe_acceleration[l] = continuum->F.local_element(l) / continuum->mass.local_element(l);
    record_initial_state(n_steps, t0);
    pcout << "Newmark (beta " << beta << ", gamma " << gamma << "): " << n_steps << " steps of " << sci(dt, 6)
          << " from t = " << t0 << "; tangent " << describe_tangent() << std::endl;

    std::vector<double> v_predicted(n);
    const auto          start        = std::chrono::steady_clock::now();
    unsigned int        total_newton = 0, total_linear = 0;
    u_predicted.resize(n);
    for (unsigned int step = 1; step <= n_steps; ++step)
      {
        const double time = t0 + step * dt;
        pcout << "Step " << step << "/" << n_steps << ", t = " << sci(time, 6) << std::endl;
        const LoadPathState step_start = load_path_state();
        for (unsigned int k = 0; k < n; ++k)
          {
            u_predicted[k] = u[k] + dt * v[k] + 0.5 * dt * dt * (1 - 2 * beta) * acceleration[k];
            v_predicted[k] = v[k] + dt * (1 - gamma) * acceleration[k];
            u[k]           = u_predicted[k];
          }
        for (unsigned int j = 0; j < fe_dofs.size(); ++j)
          {
            const unsigned int l = fe_dofs[j];
            fe_u_predicted[l]    = U[l] + dt * V[l] + 0.5 * dt * dt * (1 - 2 * beta) * fe_acceleration[l];
            fe_v_predicted[j]    = V[l] + dt * (1 - gamma) * fe_acceleration[l];
            U[l]                 = fe_u_predicted[l];
          }
        apply_prescribed(time, dt);
        if (loads_depend_on_time)
          evaluate_loads(time);
        check_condition_values(first_nonfinite_condition(time), time);
        newmark_inertia = 1 / (beta * dt * dt);
        solve_step(step);
        total_newton += last_newton.newton_iterations;
        total_linear += last_newton.linear_iterations;
        for (unsigned int k = 0; k < n; ++k)
          {
            acceleration[k] = (u[k] - u_predicted[k]) * newmark_inertia;
            v[k]            = v_predicted[k] + gamma * dt * acceleration[k];
          }
        for (unsigned int j = 0; j < fe_dofs.size(); ++j)
          {
            const unsigned int l = fe_dofs[j];
            fe_acceleration[l]   = (U[l] - fe_u_predicted[l]) * newmark_inertia;
            V[l]                 = fe_v_predicted[j] + gamma * dt * fe_acceleration[l];
          }
        if (has_continuum && continuum->hanging.n_constraints() > 0)
          continuum->hanging.distribute(continuum->V);
        displacement.update_ghost_values();
        compute_forces(true);
        external_work += load_path_work(step_start);
        if (output.is_output_step(step, n_steps))
          write_output(step, time, output.is_globals_step(step, n_steps), output.is_field_step(step, n_steps));
        // SIGTERM, SIGINT: stop after the step (one reduction per step).
        if (interrupt_signal(comm) != 0)
          stop_interrupted(step, time, n_steps,
                           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    pcout << "\nNewmark: " << n_steps << " steps, " << total_newton << " Newton iterations, " << total_linear
          << " " << implicit.linear_solver << " iterations in " << sci(seconds, 4) << " s" << std::endl;
    global_quantities(n_steps, t0 + n_steps * dt);
    print_summary(seconds, n_steps);
  }

  double
  Simulation::support_force(const Constraint &c) const
  {
    const unsigned int k = dim * c.point + c.component;
    return (acceleration.empty() ? 0.0 : mass_density[c.point] * cloud.volume[c.point] * acceleration[k]) -
           cloud.volume[c.point] * force.local_element(k);
  }

  double
  Simulation::node_support_force(const NodeConstraint &c) const
  {
    const unsigned int l = continuum->nodes[c.node].local;
    return (fe_acceleration.empty() ? 0.0 : continuum->mass.local_element(l) * fe_acceleration[l]) -
           continuum->F.local_element(l);
  }

  Simulation::LoadPathState
  Simulation::load_path_state() const
  {
    LoadPathState s;
    for (const auto &c : constraints)
      s.support.push_back(support_force(c));
    for (const auto &c : node_constraints)
      s.node_support.push_back(node_support_force(c));
    s.u.assign(displacement.begin(), displacement.begin() + dim * cloud.n_owned());
    s.body = body_force;
    if (has_continuum)
      {
        s.fe_u.assign(continuum->U.begin(), continuum->U.begin() + continuum->U.locally_owned_size());
        if (continuum->load.size() > 0)
          s.load.assign(continuum->load.begin(), continuum->load.begin() + continuum->load.locally_owned_size());
      }
    return s;
  }

  double
  Simulation::load_path_work(const LoadPathState &start) const
  {
    // Trapezoidal sums of force x displacement increment: exact while the
    // forces change linearly over the step (a linear material, small strain).
    double        work = 0;
    const double *u    = displacement.begin();
    for (unsigned int c = 0; c < constraints.size(); ++c)
      {
        const unsigned int k = dim * constraints[c].point + constraints[c].component;
        work += 0.5 * (start.support[c] + support_force(constraints[c])) * (u[k] - start.u[k]);
      }
    // A body force on a prescribed entry is balanced by its support.
    for (unsigned int k = 0; k < body_force.size(); ++k)
      if (!constrained_dofs[k])
        work += 0.5 * (start.body[k] + body_force[k]) * cloud.volume[k / dim] * (u[k] - start.u[k]);
    if (has_continuum)
      {
        const double *U = continuum->U.begin();
        for (unsigned int c = 0; c < node_constraints.size(); ++c)
          {
            const unsigned int l = continuum->nodes[node_constraints[c].node].local;
            work += 0.5 * (start.node_support[c] + node_support_force(node_constraints[c])) * (U[l] - start.fe_u[l]);
          }
        if (!start.load.empty())
          {
            const std::vector<std::uint8_t> prescribed = fe_prescribed_flags();
            for (const unsigned int l : continuum->free)
              if (!prescribed[l])
                work += 0.5 * (start.load[l] + continuum->load.local_element(l)) * (U[l] - start.fe_u[l]);
          }
      }
    return Utilities::MPI::sum(work, comm);
  }

  std::size_t
  Simulation::break_bonds()
  {
    TimerOutput::Scope t(timer, "damage");
    displacement.update_ghost_values();
    ModelState state{cloud, bonds, broken.data(), displacement.begin(), force.begin(), nullptr, *fields};
    std::size_t newly = 0;
    for (unsigned int k = 0; k < blocks.size(); ++k)
      newly += damage_pass(blocks[k].damage.get(), stretch_limits, k, state, blocks[k].points, broken.data());
    broken_bond_count += newly;
    return Utilities::MPI::sum(newly, comm);
  }
} // namespace perideal
