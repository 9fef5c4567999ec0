// The continuum model (LinearElasticity on FE_Q(p)^3) against classical
// solutions, on a bar [0,4] x [0,1] x [0,1] of K = 1, G = 0.6, rho = 1.
//
// 1. Uniaxial traction sigma = 1e-3 on x = 4, rollers on x = 0, y = 0, z = 0:
//    u = sigma/E (x, -nu y, -nu z) is linear, so Q1 and Q2 reproduce it to
//    round-off (max nodal error below 1e-9 of max |u|; the linear solver
//    stops at 1e-13).
// 2. A bar under its own weight (body force b_x = 1, sigma_xx = 4 - x, free
//    lateral stresses), the exact displacement
//      u_x = (x (4 - x/2) - nu (y^2 + z^2)/2) / E,
//      u_y = -nu (4 - x) y / E,  u_z = -nu (4 - x) z / E
//    on the whole boundary: quadratic, so Q2 is exact to round-off; Q1's L2
//    error falls with the mesh at order 2 (checked within 1.9 to 2.1 between
//    2 and 4 cells across; the errors are printed).
// 3. Stable explicit step: the element bound of LinearElasticity
//    (2 / sqrt(max over cells of lambda_max(M_e^-1 K_e))) is below the true
//    limit 2 / omega_max of the lumped free bar (omega_max by power iteration
//    on M^-1 K) and above half of it, for Q1 and Q2; both printed against
//    h / c_p (measured: Q1 0.775 against 0.964, the row-sum Gershgorin
//    bound 0.766; Q2 0.304 against 0.330, Gershgorin 0.177).
// Runs on 1 and 2 ranks; the stored output compares them.

#include "harness.h"

#include <perideal/continuum/linear_elasticity.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/numerics/vector_tools.h>

using namespace pdtest;

namespace
{
  constexpr double L = 4, Kmod = 1, Gmod = 0.6, rho = 1;

  class Bar
  {
  public:
    Bar(const MPI_Comm comm, const unsigned int n, const unsigned int p)
      : comm(comm)
      , triangulation(comm)
      , fe(FE_Q<3>(p), 3)
      , dof_handler(triangulation)
      , model(Kmod, Gmod, rho)
      , quadrature(p + 1)
      , face_quadrature(p + 1)
    {
      // Boundary ids of a colorized box: x = 0, 4 -> 0, 1; y -> 2, 3; z -> 4, 5.
      GridGenerator::subdivided_hyper_rectangle(triangulation, {4 * n, n, n}, Point<3>(0, 0, 0), Point<3>(L, 1, 1),
                                                true);
      dof_handler.distribute_dofs(fe);
      owned    = dof_handler.locally_owned_dofs();
      DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
      h        = 1.0 / n;
    }

    /// Assembles K u = f with @p constraints (built on the relevant DoFs) and
    /// solves it by CG with AMG; returns the ghosted solution.
    TrilinosWrappers::MPI::Vector
    solve(const AffineConstraints<double> &constraints, const Tensor<1, 3> &body_force,
          const types::boundary_id traction_id, const Tensor<1, 3> &traction)
    {
      DynamicSparsityPattern dsp(relevant);
      DoFTools::make_sparsity_pattern(dof_handler, dsp, constraints, false);
      SparsityTools::distribute_sparsity_pattern(dsp, owned, comm, relevant);
      TrilinosWrappers::SparseMatrix matrix;
      matrix.reinit(owned, owned, dsp, comm);
      TrilinosWrappers::MPI::Vector rhs(owned, comm), x(owned, comm);

      FEValues<3>     fe_values(fe, quadrature, update_values | update_gradients | update_JxW_values);
      FEFaceValues<3> fe_face_values(fe, face_quadrature, update_values | update_JxW_values);
      FullMatrix<double>                   cell_matrix;
      Vector<double>                       cell_rhs, face_rhs;
      std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            fe_values.reinit(cell);
            model.cell_matrix(fe_values, cell_matrix);
            perideal::LinearElasticity::cell_body_force(fe_values, body_force, cell_rhs);
            for (const unsigned int f : cell->face_indices())
              if (cell->at_boundary(f) && cell->face(f)->boundary_id() == traction_id)
                {
                  fe_face_values.reinit(cell, f);
                  perideal::LinearElasticity::face_traction(fe_face_values, traction, face_rhs);
                  cell_rhs += face_rhs;
                }
            cell->get_dof_indices(dofs);
            constraints.distribute_local_to_global(cell_matrix, cell_rhs, dofs, matrix, rhs);
          }
      matrix.compress(VectorOperation::add);
      rhs.compress(VectorOperation::add);

      TrilinosWrappers::PreconditionAMG                 amg;
      TrilinosWrappers::PreconditionAMG::AdditionalData data;
      data.elliptic = true;
      amg.initialize(matrix, data);
      SolverControl                               control(2000, 1e-13 * rhs.l2_norm());
      SolverCG<TrilinosWrappers::MPI::Vector>     cg(control);
      cg.solve(matrix, x, rhs, amg);
      constraints.distribute(x);
      TrilinosWrappers::MPI::Vector ghosted(owned, relevant, comm);
      ghosted = x;
      return ghosted;
    }

    /// max over nodes of |u_h - u| / max |u| (support points of the DoFs).
    double
    max_nodal_error(const TrilinosWrappers::MPI::Vector &u, const Function<3> &exact) const
    {
      TrilinosWrappers::MPI::Vector interpolated(owned, comm);
      VectorTools::interpolate(dof_handler, exact, interpolated);
      double err = 0, size = 0;
      for (const auto i : owned)
        {
          err  = std::max(err, std::abs(u[i] - interpolated[i]));
          size = std::max(size, std::abs(interpolated[i]));
        }
      return Utilities::MPI::max(err, comm) / Utilities::MPI::max(size, comm);
    }

    /// || u_h - u ||_L2 / || u ||_L2.
    double
    l2_error(const TrilinosWrappers::MPI::Vector &u, const Function<3> &exact) const
    {
      Vector<float> cellwise(triangulation.n_active_cells());
      VectorTools::integrate_difference(dof_handler, u, exact, cellwise, QGauss<3>(fe.degree + 2),
                                        VectorTools::L2_norm);
      const double err = VectorTools::compute_global_error(triangulation, cellwise, VectorTools::L2_norm);
      Functions::ZeroFunction<3> zero(3);
      VectorTools::integrate_difference(dof_handler, u, zero, cellwise, QGauss<3>(fe.degree + 2),
                                        VectorTools::L2_norm);
      return err / VectorTools::compute_global_error(triangulation, cellwise, VectorTools::L2_norm);
    }

    /// The element-bound step of LinearElasticity and the true limit 2/omega_max
    /// of the free, lumped bar (power iteration on M^-1 K).
    std::pair<double, double>
    stable_steps()
    {
      AffineConstraints<double> none;
      none.close();
      DynamicSparsityPattern dsp(relevant);
      DoFTools::make_sparsity_pattern(dof_handler, dsp, none, false);
      SparsityTools::distribute_sparsity_pattern(dsp, owned, comm, relevant);
      TrilinosWrappers::SparseMatrix matrix;
      matrix.reinit(owned, owned, dsp, comm);
      TrilinosWrappers::MPI::Vector mass(owned, comm);

      FEValues<3> fe_values(fe, quadrature, update_values | update_gradients | update_JxW_values);
      FullMatrix<double>                   cell_matrix;
      Vector<double>                       cell_mass;
      std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
      double                               dt_element = std::numeric_limits<double>::max();
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            fe_values.reinit(cell);
            model.cell_matrix(fe_values, cell_matrix);
            model.cell_lumped_mass(fe_values, cell_mass);
            dt_element = std::min(dt_element, perideal::LinearElasticity::stable_time_step(cell_matrix, cell_mass));
            cell->get_dof_indices(dofs);
            none.distribute_local_to_global(cell_matrix, dofs, matrix);
            mass.add(dofs, cell_mass);
          }
      matrix.compress(VectorOperation::add);
      mass.compress(VectorOperation::add);

      dt_element = Utilities::MPI::min(dt_element, comm);

      // Power iteration on M^-1/2 K M^-1/2 (symmetric, same eigenvalues).
      TrilinosWrappers::MPI::Vector x(owned, comm), y(owned, comm);
      for (const auto i : owned)
        x[i] = 1.0 + 0.37 * std::sin(1.3 * i) * (i % 3 == 0 ? -1 : 1);
      x.compress(VectorOperation::insert);
      double lambda = 0;
      for (unsigned int it = 0; it < 3000; ++it)
        {
          x /= x.l2_norm();
          for (const auto i : owned)
            y[i] = x[i] / std::sqrt(mass[i]);
          y.compress(VectorOperation::insert);
          TrilinosWrappers::MPI::Vector Ky(owned, comm);
          matrix.vmult(Ky, y);
          for (const auto i : owned)
            Ky[i] /= std::sqrt(mass[i]);
          Ky.compress(VectorOperation::insert);
          lambda = x * Ky;
          x      = Ky;
        }
      return {dt_element, 2 / std::sqrt(lambda)};
    }

    MPI_Comm                                  comm;
    parallel::distributed::Triangulation<3> triangulation;
    FESystem<3>                               fe;
    DoFHandler<3>                             dof_handler;
    perideal::LinearElasticity                model;
    QGauss<3>                                 quadrature;
    QGauss<2>                                 face_quadrature;
    IndexSet                                  owned, relevant;
    double                                    h = 0;
  };

  class Uniaxial : public Function<3>
  {
  public:
    Uniaxial(const double sigma, const double E, const double nu)
      : Function<3>(3)
      , s(sigma / E)
      , nu(nu)
    {}
    double
    value(const Point<3> &x, const unsigned int c) const override
    {
      return c == 0 ? s * x[0] : -nu * s * x[c];
    }
    const double s, nu;
  };

  class OwnWeight : public Function<3>
  {
  public:
    OwnWeight(const double E, const double nu)
      : Function<3>(3)
      , E(E)
      , nu(nu)
    {}
    double
    value(const Point<3> &x, const unsigned int c) const override
    {
      if (c == 0)
        return (x[0] * (L - x[0] / 2) - nu * (x[1] * x[1] + x[2] * x[2]) / 2) / E;
      return -nu * (L - x[0]) * x[c] / E;
    }
    const double E, nu;
  };

} // namespace

int
main(int argc, char *argv[])
{
  return run_checks(argc, argv, [](const MPI_Comm comm, Report &report) {
    const perideal::LinearElasticity material(Kmod, Gmod, rho);
    const double                     E = material.young_modulus(), nu = material.poisson_ratio();
    report.line("bar 4 x 1 x 1, K = 1, G = 0.6: E = " + short_number(E) + ", nu = " + short_number(nu));


    for (const unsigned int p : {1u, 2u})
      {
        Bar                       bar(comm, 2, p);
        AffineConstraints<double> rollers(bar.relevant);
        for (const auto &[id, component] : std::vector<std::pair<types::boundary_id, unsigned int>>{{0, 0}, {2, 1}, {4, 2}})
          {
            ComponentMask mask(3, false);
            mask.set(component, true);
            VectorTools::interpolate_boundary_values(bar.dof_handler, id, Functions::ZeroFunction<3>(3), rollers, mask);
          }
        rollers.close();
        const double sigma = 1e-3;
        const auto   u     = bar.solve(rollers, Tensor<1, 3>(), 1, Tensor<1, 3>({sigma, 0, 0}));
        report.below("Q" + std::to_string(p) + " uniaxial traction: max nodal error / max |u|",
              bar.max_nodal_error(u, Uniaxial(sigma, E, nu)), 1e-9);
      }

    const OwnWeight exact(E, nu);
    std::map<unsigned int, double> q1_error;
    for (const unsigned int p : {1u, 2u})
      for (const unsigned int n : (p == 1 ? std::vector<unsigned int>{2, 4} : std::vector<unsigned int>{2}))
        {
          Bar                       bar(comm, n, p);
          AffineConstraints<double> dirichlet(bar.relevant);
          for (const types::boundary_id id : {0, 1, 2, 3, 4, 5})
            VectorTools::interpolate_boundary_values(bar.dof_handler, id, exact, dirichlet);
          dirichlet.close();
          const auto u = bar.solve(dirichlet, Tensor<1, 3>({1, 0, 0}), numbers::invalid_boundary_id, Tensor<1, 3>());
          if (p == 2)
            report.below("Q2 own weight, 2 cells across: max nodal error / max |u|", bar.max_nodal_error(u, exact), 1e-9);
          else
            {
              q1_error[n] = bar.l2_error(u, exact);
              report.value("Q1 own weight, " + std::to_string(n) + " cells across: L2 error / L2 norm", q1_error[n]);
            }
        }
    const double order = std::log2(q1_error[2] / q1_error[4]);
    report.check("Q1 own weight: L2 convergence order", order, order > 1.9 && order < 2.1, "2 +- 0.1");

    for (const unsigned int p : {1u, 2u})
      {
        Bar          bar(comm, 2, p);
        const auto   dt = bar.stable_steps();
        const double cfl = bar.h / material.p_wave_speed();
        report.value("Q" + std::to_string(p) + " stable step / (h / c_p): element bound", dt.first / cfl);
        report.value("Q" + std::to_string(p) + " stable step / (h / c_p): 2 / omega_max", dt.second / cfl);
        const double ratio = dt.first / dt.second;
        report.check("Q" + std::to_string(p) + " element-bound step / true limit", ratio, ratio <= 1 && ratio > 0.5,
                     "in (0.5, 1]");
      }
  });
}
