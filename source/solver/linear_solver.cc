// The linear solve of a Newton iteration (implicit_solver.h): K du = R by CG
// or GMRES with AMG (rigid-body modes as near null space, the hierarchy
// reused while the iterations stay low) or Jacobi on the assembled tangent,
// or Jacobian-free with the analytic diagonal blocks as preconditioner.

#include <perideal/base/format.h>
#include <perideal/solver/implicit_solver.h>

#include <deal.II/base/mpi.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>
#include <deal.II/lac/trilinos_vector.h>

#include <Epetra_MultiVector.h>
#include <Teuchos_ParameterList.hpp>

#include <cmath>
#include <functional>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    /// An operator from a function, for deal.II's solvers.
    template <typename Vector>
    struct FunctionOperator
    {
      std::function<void(Vector &, const Vector &)> apply;
      void
      vmult(Vector &dst, const Vector &src) const
      {
        apply(dst, src);
      }
    };
  } // namespace

  unsigned int
  ImplicitSolver::solve_linear(const std::vector<double> &R, std::vector<double> &du)
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
        if (residual_products())
          SolverGMRES<TrilinosWrappers::MPI::Vector>(control).solve(
            FunctionOperator<TrilinosWrappers::MPI::Vector>{residual_operator(R, first)}, x, rhs, preconditioner);
        else if (linear_solver == "CG")
          SolverCG<TrilinosWrappers::MPI::Vector>(control).solve(matrix, x, rhs, preconditioner);
        else
          SolverGMRES<TrilinosWrappers::MPI::Vector>(control).solve(matrix, x, rhs, preconditioner);
      }
    catch (const SolverControl::NoConvergence &e)
      {
        restore_unknowns();
        AssertThrow(false,
                    ExcMessage("the linear solver (" + linear_solver + ", " + implicit.preconditioner +
                               ") did not converge in " + std::to_string(e.last_step) + " iterations (residual " +
                               sci(e.last_residual) + ", wanted " + sci(control.tolerance()) +
                               "): raise Solver/Implicit/Maximum linear iterations, or the tangent is "
                               "singular (a part of the body held by no condition, e.g. a fragment)"));
      }
    restore_unknowns();
    if (!reuse)
      amg_iterations = control.last_step();
    rebuild_amg = reuse && control.last_step() > 2 * amg_iterations + 5;
    for (unsigned int k = 0; k < du.size(); ++k)
      du[k] = x[first + k];
    return control.last_step();
  }

  std::function<void(TrilinosWrappers::MPI::Vector &, const TrilinosWrappers::MPI::Vector &)>
  ImplicitSolver::residual_operator(const std::vector<double> &R, const types::global_dof_index first)
  {
    // K v = -(R(z + e v) - R(z))/e over the unknowns z (R: the residual at
    // z, which restore_unknowns() puts back), e as Jacobian = Matrix free's.
    const unsigned int n = R.size();
    z_saved.resize(n);
    r_plus.resize(n);
    double z_norm = 0;
    for (unsigned int k = 0; k < n; ++k)
      {
        z_saved[k] = unknown(k);
        z_norm += z_saved[k] * z_saved[k];
      }
    z_norm = std::sqrt(Utilities::MPI::sum(z_norm, comm));
    return [this, &R, first, n, z_norm](TrilinosWrappers::MPI::Vector &dst, const TrilinosWrappers::MPI::Vector &src) {
      const double v_norm = src.l2_norm();
      if (v_norm == 0)
        {
          dst = 0;
          return;
        }
      const double e = 1e-8 * (1 + z_norm) / v_norm;
      for (unsigned int k = 0; k < n; ++k)
        unknown(k) = z_saved[k] + e * src[first + k];
      double forces = 0;
      residual(r_plus, forces);
      for (unsigned int k = 0; k < n; ++k)
        dst[first + k] = -(r_plus[k] - R[k]) / e;
      dst.compress(VectorOperation::insert);
    };
  }

  void
  ImplicitSolver::restore_unknowns()
  {
    for (unsigned int k = 0; k < z_saved.size(); ++k)
      unknown(k) = z_saved[k];
    z_saved.clear();
  }

  unsigned int
  ImplicitSolver::solve_matrix_free(const std::vector<double> &R, std::vector<double> &du)
  {
    TimerOutput::Scope  t(timer, "implicit: linear solve");
    const unsigned int  n = R.size();
    VectorType          rhs(tangent->owned, comm), x(tangent->owned, comm);
    std::vector<double> u0(n), R_plus(n);
    for (unsigned int k = 0; k < n; ++k)
      {
        rhs.local_element(k) = R[k];
        u0[k]                = state.displacement.local_element(k);
      }
    double u_norm = 0;
    for (const double v : u0)
      u_norm += v * v;
    u_norm = std::sqrt(Utilities::MPI::sum(u_norm, comm));

    // K v = -dR/du v by a forward difference of the residual; identity rows
    // at the prescribed DoFs.
    const FunctionOperator<VectorType> K{[&](VectorType &dst, const VectorType &src) {
      const double v_norm = src.l2_norm();
      if (v_norm == 0)
        {
          dst = 0;
          return;
        }
      const double e = 1e-8 * (1 + u_norm) / v_norm;
      for (unsigned int k = 0; k < n; ++k)
        state.displacement.local_element(k) = u0[k] + e * src.local_element(k);
      double forces = 0;
      residual(R_plus, forces);
      for (unsigned int k = 0; k < n; ++k)
        dst.local_element(k) = constrained_dofs[k] ? src.local_element(k) : -(R_plus[k] - R[k]) / e;
    }};
    const FunctionOperator<VectorType> P{[&](VectorType &dst, const VectorType &src) {
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
        state.displacement.local_element(k) = u0[k];
      }
    return control.last_step();
  }

  std::string
  ImplicitSolver::describe_tangent() const
  {
    const double bytes = Utilities::MPI::sum(double(tangent->memory_consumption()), comm);
    if (implicit.jacobian == "Matrix free")
      return "matrix free (" + implicit.linear_solver + ", block Jacobi from the analytic diagonal; " + sci(bytes / 1048576.0, 4) + " MiB)";
    if (has_continuum)
      return std::string(use_finite_differences ? "by finite differences" : "analytic") + ", PD part " +
             std::to_string(tangent->matrix.n_nonzero_elements()) + " nonzeros, coupled " +
             (force_blending ? "N A T + D K_FE (force blending" +
                                 std::string(residual_products() ? ", products from the residual" : "") + ") on " :
                               "T^T A T + K_FE on ") +
             std::to_string(coupled_tangent->owned.size()) + " free DoFs (" +
             sci(Utilities::MPI::sum(double(coupled_tangent->memory_consumption()), comm) / 1048576.0 +
                   bytes / 1048576.0, 4) +
             " MiB), " + linear_solver + " with " + implicit.preconditioner;
    return std::string(use_finite_differences ? "by finite differences" : "analytic") + ", " +
           std::to_string(tangent->matrix.n_nonzero_elements()) + " nonzeros (" + sci(bytes / 1048576.0, 4) +
           " MiB), " + implicit.linear_solver + " with " + implicit.preconditioner;
  }
} // namespace perideal
