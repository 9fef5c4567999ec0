// PointInterpolation (the coupling's Pi and Pi^T, doc/coupling.md) on FE_Q(p)^3,
// p = 1, 2, of a curved box mesh (4 x 2 x 2 cells of [0,2] x [0,1] x [0,1]
// moved by a smooth map, Q1 geometry). Two points per locally owned cell: its
// centre and the image of the unit-cell point (0.2, 0.7, 0.4). Checked, on 1
// and 2 ranks:
// 1. Pi reproduces a linear field g(x) = A x + b (in the FE space of an
//    isoparametric or higher element): max |Pi U - g(x_k)| below 1e-13 of
//    max |g| (this also checks the inverse mapping of the points);
// 2. Pi^T keeps the sum of the point forces (the shape functions sum to one):
//    |sum_a F_a - sum_k f_k| below 1e-14 of sum_k |f_k|, F = Pi^T f;
// 3. Pi^T is the transpose: sum_k f_k . (Pi U)_k = F . U to 1e-13.

#include "harness.h"

#include <perideal/continuum/continuum_field.h>
#include <perideal/continuum/point_interpolation.h>

#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/vector_tools.h>

using namespace pdtest;


int
main(int argc, char *argv[])
{
  return run_checks(argc, argv, [](const MPI_Comm comm, Report &report) {
    parallel::distributed::Triangulation<3> triangulation(comm);
    GridGenerator::subdivided_hyper_rectangle(triangulation, {4, 2, 2}, Point<3>(0, 0, 0), Point<3>(2, 1, 1));
    GridTools::transform(
      [](const Point<3> &x) {
        return Point<3>(x[0] + 0.08 * std::sin(3 * x[1]) * x[2], x[1] + 0.05 * x[0] * x[0], x[2] + 0.06 * std::cos(2 * x[0]) * x[1]);
      },
      triangulation);
    const MappingQ1<3> mapping;
    // A linear field g(x) = A x + b.
    const auto g = vector_function([](const Point<3> &x) {
      const double A[3][3] = {{0.3, -1.1, 0.7}, {0.2, 0.5, -0.4}, {-0.9, 0.1, 1.3}}, b[3] = {0.1, -0.2, 0.3};
      Tensor<1, 3> v;
      for (unsigned int c = 0; c < 3; ++c)
        v[c] = A[c][0] * x[0] + A[c][1] * x[1] + A[c][2] * x[2] + b[c];
      return v;
    });

    for (const unsigned int p : {1u, 2u})
      {
        const FESystem<3> fe(FE_Q<3>(p), 3);
        DoFHandler<3>     dof_handler(triangulation);
        dof_handler.distribute_dofs(fe);
        IndexSet relevant;
        DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
        using VectorType = perideal::PointInterpolation::VectorType;
        VectorType U(dof_handler.locally_owned_dofs(), relevant, comm);
        VectorTools::interpolate(mapping, dof_handler, g, U);
        U.update_ghost_values();

        std::vector<std::pair<DoFHandler<3>::active_cell_iterator, Point<3>>> points;
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            for (const Point<3> &unit : {Point<3>(0.5, 0.5, 0.5), Point<3>(0.2, 0.7, 0.4)})
              points.emplace_back(cell, mapping.transform_unit_to_real_cell(cell, unit));
        perideal::PointInterpolation interpolation;
        interpolation.reinit(dof_handler, points);
        const unsigned int n = Utilities::MPI::sum(interpolation.n_points(), comm);
        report.line("Q" + std::to_string(p) + ": " + std::to_string(n) + " points, " +
                    std::to_string(dof_handler.n_dofs()) + " DoFs");

        // 1. Linear fields.
        std::vector<double> u;
        interpolation.interpolate(U, u);
        double err = 0, size = 0;
        for (unsigned int k = 0; k < points.size(); ++k)
          for (unsigned int c = 0; c < 3; ++c)
            {
              err  = std::max(err, std::abs(u[3 * k + c] - g.value(points[k].second, c)));
              size = std::max(size, std::abs(g.value(points[k].second, c)));
            }
        report.below("  max |Pi U - g| / max |g| at the points", Utilities::MPI::max(err, comm) / Utilities::MPI::max(size, comm),
                     1e-13);

        // 2. Momentum and 3. transpose, with forces that depend on the position only.
        std::vector<double> f(3 * points.size());
        for (unsigned int k = 0; k < points.size(); ++k)
          for (unsigned int c = 0; c < 3; ++c)
            f[3 * k + c] = std::sin(1.7 * points[k].second[0] + 2.3 * c) + 0.5 * points[k].second[c];
        VectorType F(dof_handler.locally_owned_dofs(), relevant, comm);
        interpolation.add_transpose(f, F);
        F.compress(VectorOperation::add);

        // The component of each owned DoF.
        const IndexSet           &owned = dof_handler.locally_owned_dofs();
        std::vector<unsigned int> component(owned.n_elements());
        for (const auto &node : perideal::owned_nodes(dof_handler))
          component[node.local] = node.component;
        double sums[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}; // sum f (3), sum |f|, sum F (3), f . Pi U, F . U
        for (unsigned int k = 0; k < points.size(); ++k)
          for (unsigned int c = 0; c < 3; ++c)
            {
              sums[c] += f[3 * k + c];
              sums[3] += std::abs(f[3 * k + c]);
              sums[7] += f[3 * k + c] * u[3 * k + c];
            }
        for (unsigned int i = 0; i < owned.n_elements(); ++i)
          {
            sums[4 + component[i]] += F.local_element(i);
            sums[8] += F.local_element(i) * U.local_element(i);
          }
        Utilities::MPI::sum(ArrayView<const double>(sums, 9), comm, ArrayView<double>(sums, 9));
        double momentum = 0;
        for (unsigned int c = 0; c < 3; ++c)
          momentum = std::max(momentum, std::abs(sums[4 + c] - sums[c]));
        report.below("  max_c |sum F_c - sum f_c| / sum |f|", momentum / sums[3], 1e-14);
        report.below("  |f . Pi U - Pi^T f . U| / |f . Pi U|", std::abs(sums[7] - sums[8]) / std::abs(sums[7]), 1e-13);
      }
  });
}
