// What deal.II's DoF numbering costs on a mesh like the Kalthoff-Winkler
// plate's (doc/adaptivity.md, "The DoF numbering"): DoFHandler::
// distribute_dofs() with two elements in the mesh (hp: FE_DGQ(0)^3 on PD
// cells, FE_Q(1)^3 on FE cells, or FE_Nothing on the PD cells) against one
// element on every cell. A conversion that changed a cell's element paid
// the first; a conversion that keeps the numbering pays none.
//
// usage (bench/dof_numbering.sh builds and runs it):
//   mpirun -np N dof_numbering [NX NY NZ]   (default 100 200 10 cells)
// Prints the best of 3 wall times (between barriers) of each case.

#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_dgq.h>
#include <deal.II/fe/fe_nothing.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/hp/fe_collection.h>

#include <algorithm>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <string>

using namespace dealii;

namespace
{
  constexpr int dim = 3;

  /// The best of three wall times of @p work, each between two barriers.
  double
  best_time(const MPI_Comm comm, const std::function<void()> &work)
  {
    double best = 1e300;
    for (int r = 0; r < 3; ++r)
      {
        MPI_Barrier(comm);
        Timer timer;
        work();
        MPI_Barrier(comm);
        best = std::min(best, timer.wall_time());
      }
    return best;
  }

  /// Cells with centre x below @p fraction of the plate's width take element
  /// 0 of @p fe, the others element 1; then the DoFs are numbered.
  double
  two_elements(parallel::distributed::Triangulation<dim> &mesh, const hp::FECollection<dim> &fe,
               const double fraction, const double width)
  {
    DoFHandler<dim> dofs(mesh);
    for (const auto &cell : dofs.active_cell_iterators())
      if (cell->is_locally_owned())
        cell->set_active_fe_index(cell->center()[0] < fraction * width ? 0 : 1);
    return best_time(mesh.get_communicator(), [&]() { dofs.distribute_dofs(fe); });
  }

  double
  one_element(parallel::distributed::Triangulation<dim> &mesh, const FiniteElement<dim> &fe)
  {
    DoFHandler<dim> dofs(mesh);
    return best_time(mesh.get_communicator(), [&]() { dofs.distribute_dofs(fe); });
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                   comm = MPI_COMM_WORLD;
  const unsigned int nx = argc > 3 ? std::atoi(argv[1]) : 100, ny = argc > 3 ? std::atoi(argv[2]) : 200,
                     nz = argc > 3 ? std::atoi(argv[3]) : 10;
  const double width = 0.1;
  parallel::distributed::Triangulation<dim> mesh(comm);
  GridGenerator::subdivided_hyper_rectangle(mesh, {nx, ny, nz}, Point<dim>(0, -0.1, 0), Point<dim>(width, 0.1, 0.01));

  const FESystem<dim>       q1(FE_Q<dim>(1), dim), dg0(FE_DGQ<dim>(0), dim), nothing(FE_Nothing<dim>(), dim);
  const hp::FECollection<dim> dg0_q1(dg0, q1), nothing_q1(nothing, q1);
  ConditionalOStream          out(std::cout, Utilities::MPI::this_mpi_process(comm) == 0);
  out << "cells: " << mesh.n_global_active_cells() << " on " << Utilities::MPI::n_mpi_processes(comm)
      << " rank(s); distribute_dofs, best of 3 (s)\n";
  for (const double fraction : {0.3, 0.7})
    {
      const std::string pd = std::to_string(int(100 * fraction)) + "% of the cells";
      out << "  FE_DGQ(0)^3 on " << pd << ", FE_Q(1)^3 on the rest: " << two_elements(mesh, dg0_q1, fraction, width)
          << "\n";
      out << "  FE_Nothing^3 on " << pd << ", FE_Q(1)^3 on the rest: "
          << two_elements(mesh, nothing_q1, fraction, width) << "\n";
    }
  out << "  FE_Q(1)^3 on every cell: " << one_element(mesh, q1) << "\n";
  out << "  FE_DGQ(0)^3 on every cell: " << one_element(mesh, dg0) << "\n";
}
