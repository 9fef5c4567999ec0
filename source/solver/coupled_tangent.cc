#include <perideal/solver/coupled_tangent.h>

#include <deal.II/base/mpi.h>
#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/lac/trilinos_vector.h>

#include <EpetraExt_MatrixMatrix.h>

#include <cmath>

namespace perideal
{
  using namespace dealii;
  using Index = types::global_dof_index;

  namespace
  {
    /// C = op(A) B by EpetraExt, into a deal.II matrix.
    void
    multiply(const TrilinosWrappers::SparseMatrix &A,
             const bool                            transpose_A,
             const TrilinosWrappers::SparseMatrix &B,
             TrilinosWrappers::SparseMatrix       &C)
    {
      const Epetra_CrsMatrix &a = A.trilinos_matrix();
      Epetra_CrsMatrix c(Copy, transpose_A ? a.DomainMap() : a.RangeMap(), 0);
      const int error = EpetraExt::MatrixMatrix::Multiply(a, transpose_A, B.trilinos_matrix(), false, c, true);
      AssertThrow(error == 0, ExcMessage("EpetraExt::MatrixMatrix::Multiply failed with code " + std::to_string(error)));
      C.reinit(c, true);
    }
  } // namespace

  void
  CoupledTangent::reinit(const std::vector<NodeRow>                              *node_rows,
                         const std::vector<unsigned int>                          &pd_free,
                         const std::vector<unsigned int>                          &fe_free,
                         const std::vector<unsigned int>                          &virtual_points,
                         const PointInterpolation                                 &Pi,
                         const IndexSet                                           &pd_owned,
                         const std::shared_ptr<const Utilities::MPI::Partitioner> &fe_partitioner,
                         const TrilinosWrappers::SparseMatrix                     &K_FE,
                         const MPI_Comm                                            comm_)
  {
    comm    = comm_;
    pd_dofs = pd_free;
    fe_dofs = fe_free;
    const Index n_local  = pd_free.size() + fe_free.size();
    const Index n_global = Utilities::MPI::sum(n_local, comm);
    Index       first    = 0;
    MPI_Exscan(&n_local, &first, 1, Utilities::MPI::mpi_type_id_for_type<Index>, MPI_SUM, comm);
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      first = 0; // MPI_Exscan leaves rank 0's result undefined
    owned                = IndexSet(n_global);
    owned.add_range(first, first + n_local);
    owned.compress();

    // The unknown each FE DoF is, -1 if none; ghosts from their owners (Pi
    // reaches the DoFs of its cells, some owned elsewhere).
    LinearAlgebra::distributed::Vector<double> unknown_of(fe_partitioner);
    for (unsigned int k = 0; k < fe_partitioner->locally_owned_size(); ++k)
      unknown_of.local_element(k) = -1;
    for (unsigned int j = 0; j < fe_free.size(); ++j)
      unknown_of.local_element(fe_free[j]) = double(first + pd_free.size() + j);
    unknown_of.update_ghost_values();

    // T: rows of the owned PD DoFs.
    {
      TrilinosWrappers::SparsityPattern pattern(pd_owned, owned, comm);
      const auto                        add_entries = [&](const auto &add) {
        for (unsigned int j = 0; j < pd_free.size(); ++j)
          add(pd_owned.nth_index_in_set(pd_free[j]), first + j, 1.0);
        Pi.for_each_entry([&](const std::size_t row, const Index dof, const double w) {
          const double unknown = unknown_of.local_element(dof);
          if (unknown >= 0)
            add(pd_owned.nth_index_in_set(dim * virtual_points[row / dim] + row % dim), Index(unknown), w);
        });
      };
      add_entries([&](const Index r, const Index c, double) { pattern.add(r, c); });
      pattern.compress();
      T.reinit(pattern);
      add_entries([&](const Index r, const Index c, const double w) { T.add(r, c, w); });
      T.compress(VectorOperation::add);
    }
    // S: rows of the owned FE DoFs; then G = S^T K_FE S, once.
    {
      const IndexSet                   &fe_owned = fe_partitioner->locally_owned_range();
      TrilinosWrappers::SparsityPattern pattern(fe_owned, owned, comm);
      for (unsigned int j = 0; j < fe_free.size(); ++j)
        pattern.add(fe_owned.nth_index_in_set(fe_free[j]), first + pd_free.size() + j);
      pattern.compress();
      S.reinit(pattern);
      for (unsigned int j = 0; j < fe_free.size(); ++j)
        S.set(fe_owned.nth_index_in_set(fe_free[j]), first + pd_free.size() + j, 1.0);
      S.compress(VectorOperation::insert);
      TrilinosWrappers::SparseMatrix KS;
      multiply(K_FE, false, S, KS);
      multiply(S, true, KS, G);
    }
    force_blending = node_rows != nullptr;
    if (force_blending)
      reinit_force_blending(*node_rows, pd_owned, first);
  }

  void
  CoupledTangent::reinit_force_blending(const std::vector<NodeRow> &node_rows, const IndexSet &pd_owned,
                                        const Index first)
  {
    // Per FE DoF (owned, local): its unknown after the PD ones, -1 if none.
    unsigned int n_fe = 0;
    for (const unsigned int k : fe_dofs)
      n_fe = std::max(n_fe, k + 1);
    for (const NodeRow &r : node_rows)
      n_fe = std::max(n_fe, r.fe_dof + 1);
    std::vector<int> unknown_of(n_fe, -1);
    for (unsigned int j = 0; j < fe_dofs.size(); ++j)
      unknown_of[fe_dofs[j]] = int(pd_dofs.size() + j);

    // N: a free PD DoF's own row; an FE unknown's node point's row, weighted
    // (a prescribed or hanging node is no unknown).
    TrilinosWrappers::SparsityPattern pattern(owned, pd_owned, comm);
    const auto add_entries = [&](const auto &add) {
      for (unsigned int j = 0; j < pd_dofs.size(); ++j)
        add(first + j, pd_owned.nth_index_in_set(pd_dofs[j]), 1.0);
      for (const NodeRow &r : node_rows)
        if (unknown_of[r.fe_dof] >= 0)
          add(first + unknown_of[r.fe_dof], pd_owned.nth_index_in_set(r.pd_dof), r.weight);
    };
    add_entries([&](const Index row, const Index column, double) { pattern.add(row, column); });
    pattern.compress();
    N.reinit(pattern);
    add_entries([&](const Index row, const Index column, const double w) { N.set(row, column, w); });
    N.compress(VectorOperation::insert);

    // D G: the FE stiffness's rows times 1 - alpha.
    std::vector<double> scale(owned.n_elements(), 1.0);
    for (const NodeRow &r : node_rows)
      if (unknown_of[r.fe_dof] >= 0)
        scale[unknown_of[r.fe_dof]] = 1 - r.alpha;
    TrilinosWrappers::SparsityPattern diagonal(owned, owned, comm);
    for (unsigned int j = 0; j < scale.size(); ++j)
      diagonal.add(first + j, first + j);
    diagonal.compress();
    TrilinosWrappers::SparseMatrix D(diagonal), DG;
    for (unsigned int j = 0; j < scale.size(); ++j)
      D.set(first + j, first + j, scale[j]);
    D.compress(VectorOperation::insert);
    multiply(D, false, G, DG);
    G.reinit(DG.trilinos_matrix(), true);
  }

  void
  CoupledTangent::assemble(const TrilinosWrappers::SparseMatrix &A)
  {
    TrilinosWrappers::SparseMatrix AT, P;
    multiply(A, false, T, AT);
    if (force_blending)
      multiply(N, false, AT, P);
    else
      multiply(T, true, AT, P);
    Epetra_CrsMatrix *sum   = nullptr;
    const int         error = EpetraExt::MatrixMatrix::Add(P.trilinos_matrix(), false, 1.0, G.trilinos_matrix(),
                                                     false, 1.0, sum);
    AssertThrow(error == 0 && sum != nullptr,
                ExcMessage("EpetraExt::MatrixMatrix::Add failed with code " + std::to_string(error)));
    std::unique_ptr<Epetra_CrsMatrix> owner(sum);
    sum->FillComplete(P.trilinos_matrix().DomainMap(), P.trilinos_matrix().RangeMap());
    matrix.reinit(*sum, true);
  }

  void
  CoupledTangent::add_to_fe_diagonal(const std::vector<double> &values)
  {
    const Index first = owned.n_elements() ? *owned.begin() : 0;
    for (unsigned int j = 0; j < values.size(); ++j)
      {
        const Index row = first + pd_dofs.size() + j;
        matrix.add(row, row, values[j]);
      }
    matrix.compress(VectorOperation::add);
  }

  double
  CoupledTangent::symmetry_defect() const
  {
    TrilinosWrappers::MPI::Vector x(owned, comm), y(owned, comm), Kx(owned, comm), Ky(owned, comm);
    for (const Index g : owned)
      {
        x[g] = std::sin(1.3 * double(g) + 0.7);
        y[g] = std::cos(2.1 * double(g) + 0.2);
      }
    x.compress(VectorOperation::insert);
    y.compress(VectorOperation::insert);
    matrix.vmult(Kx, x);
    matrix.vmult(Ky, y);
    const double norm = std::max(Kx.l2_norm() / x.l2_norm(), Ky.l2_norm() / y.l2_norm());
    return norm > 0 ? std::abs(x * Ky - y * Kx) / (x.l2_norm() * y.l2_norm() * norm) : 0.0;
  }

  std::size_t
  CoupledTangent::memory_consumption() const
  {
    return matrix.memory_consumption() + T.memory_consumption() + S.memory_consumption() + G.memory_consumption() +
           (force_blending ? N.memory_consumption() : 0) +
           (pd_dofs.capacity() + fe_dofs.capacity()) * sizeof(unsigned int);
  }
} // namespace perideal
