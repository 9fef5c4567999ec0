// ContinuumField applies its stiffness cell by cell from the terms of its
// cells' shapes, or, when the shapes are too many to keep, through the
// assembled Trilinos matrix (continuum_field.cc). On a curved, locally
// refined mesh of FE_Q(1) and FE_Q(2) cells beside DG0 (peridynamic) cells,
// with energy weights in (0, 1], both ways give the same K U at every owned
// DoF that is not hanging (to 1e-13 of the largest entry), stiffness()
// agrees with them, and the masses and stable steps are equal. Run on 1 and
// 2 ranks (exit code 0 on success).

#include <perideal/continuum/continuum_field.h>
#include <perideal/continuum/linear_elasticity.h>

#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_dgq.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/hp/fe_collection.h>

#include <cmath>
#include <iostream>

using namespace dealii;
using namespace perideal;

namespace
{
  using VectorType = ContinuumField::VectorType;

  /// The largest |a - b| over @p field's free DoFs and the largest |a| there, over all ranks.
  std::pair<double, double>
  difference(const ContinuumField &field, const VectorType &a, const VectorType &b, const MPI_Comm comm)
  {
    double diff = 0, size = 0;
    for (const unsigned int k : field.free)
      {
        diff = std::max(diff, std::abs(a.local_element(k) - b.local_element(k)));
        size = std::max(size, std::abs(a.local_element(k)));
      }
    return {Utilities::MPI::max(diff, comm), Utilities::MPI::max(size, comm)};
  }
} // namespace

int
main(int argc, char *argv[])
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                   comm = MPI_COMM_WORLD;
  const bool                       root = Utilities::MPI::this_mpi_process(comm) == 0;

  parallel::distributed::Triangulation<dim> triangulation(comm);
  GridGenerator::subdivided_hyper_cube(triangulation, 4);
  // Every cell a shape of its own.
  GridTools::transform([](const Point<dim> &x) {
    Point<dim> y = x;
    y[0] += 0.05 * std::sin(3 * x[1] + 2 * x[2]);
    y[1] += 0.04 * std::cos(2 * x[0] - x[2]);
    y[2] += 0.03 * std::sin(x[0] + 4 * x[1]);
    return y;
  }, triangulation);
  for (const auto &cell : triangulation.active_cell_iterators())
    if (cell->is_locally_owned() && cell->center()[0] > 0.5 && cell->center()[2] < 0.5)
      cell->set_refine_flag();
  triangulation.execute_coarsening_and_refinement();

  const hp::FECollection<dim> fe(FESystem<dim>(FE_DGQ<dim>(0), dim), FESystem<dim>(FE_Q<dim>(1), dim),
                                 FESystem<dim>(FE_Q<dim>(2), dim));
  DoFHandler<dim> dof_handler(triangulation);
  for (const auto &cell : dof_handler.active_cell_iterators())
    if (cell->is_locally_owned())
      cell->set_active_fe_index(cell->center()[0] < 0.25 ? 0 : cell->center()[1] > 0.5 ? 2 : 1);
  dof_handler.distribute_dofs(fe);

  const LinearElasticity model(2.0, 1.2, 3.0);
  const auto model_of = [&](const CellIterator &cell) -> const ContinuumModel * {
    return cell->active_fe_index() == 0 ? nullptr : &model;
  };
  const auto weight_of = [](const CellIterator &cell) { return 0.5 + 0.5 * std::cos(cell->center()[0]); };

  ContinuumField by_cell, by_matrix;
  by_matrix.max_kept_bytes = 0;
  by_cell.setup(dof_handler, model_of, weight_of, comm);
  by_matrix.setup(dof_handler, model_of, weight_of, comm);

  bool ok = by_cell.applied_by_cell() && !by_matrix.applied_by_cell();
  if (root)
    std::cout << "ways: by cell " << by_cell.applied_by_cell() << ", by matrix " << !by_matrix.applied_by_cell()
              << ", hanging-node constraints " << by_cell.hanging.n_constraints() << "\n";

  for (ContinuumField *field : {&by_cell, &by_matrix})
    for (unsigned int k = 0; k < field->U.locally_owned_size(); ++k)
      field->U.local_element(k) = std::sin(0.7 * double(field->U.get_partitioner()->local_to_global(k)) + 0.3);
  VectorType cell_ku(by_cell.vector_partitioner()), matrix_ku(by_cell.vector_partitioner()),
    assembled_ku(by_cell.vector_partitioner());
  by_cell.apply_stiffness(by_cell.U, cell_ku);
  by_matrix.apply_stiffness(by_matrix.U, matrix_ku);
  by_cell.stiffness().vmult(assembled_ku, by_cell.U);

  const auto report = [&](const char *what, const std::pair<double, double> &d) {
    const bool pass = d.first <= 1e-13 * d.second && d.second > 0;
    ok &= pass;
    if (root)
      std::cout << what << ": largest difference " << d.first / d.second << " of the largest entry "
                << (pass ? "PASS" : "FAIL") << "\n";
  };
  report("K U by cell against by matrix", difference(by_cell, cell_ku, matrix_ku, comm));
  report("K U by cell against stiffness()", difference(by_cell, cell_ku, assembled_ku, comm));
  report("lumped mass", difference(by_cell, by_cell.mass, by_matrix.mass, comm));
  const double step      = by_cell.stable_time_step(); // collective
  const bool   same_step = step == by_matrix.stable_time_step();
  ok &= same_step;
  if (root)
    std::cout << "stable step " << step << " both ways: " << (same_step ? "PASS" : "FAIL")
              << "\n"
              << (ok ? "ALL PASSED" : "FAILED") << std::endl;
  return ok ? 0 : 1;
}
