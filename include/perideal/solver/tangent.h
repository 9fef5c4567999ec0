#pragma once
// The tangent stiffness of the peridynamic equations, for the implicit
// solvers: K = -dR/du with R_i = V_i f_i (the force on point i; with this
// weighting K is symmetric for every material with a strain energy), in a
// TrilinosWrappers::SparseMatrix over the degrees of freedom 3 g + c (g: the
// global point index, c: the component), rows of the owned points.
//
// Sparsity from the bonds. A bond-based material couples a point to its own
// family (1 hop). A state-based one (LPS) couples it also to its neighbors'
// families (2 hops): the owner of point i adds the rows of i and of every
// neighbor of i, each with the columns of i and its family, and the rows of
// ghost points go to their owners when the matrix is compressed. No rank
// needs the family of a point it does not own. The 2-hop form needs families
// to be symmetric (j in F(i) exactly when i in F(j)): the solver checks that
// bonded blocks share their horizon.
//
// Materials add 3x3 blocks to a buffer of the sparsity's shape (TangentRows);
// finish() moves it into the matrix once per row.
//
// Without an analytic tangent, add_finite_differences() builds it from force
// evaluations: central differences, all points of one colour perturbed at
// once. Colours come from a lattice of cubes of side s, colour = cube
// coordinates mod k with (k - 1) s > 2 reach (reach = hops x the largest
// horizon); two points of a colour in one row would have to share a cube, which
// is checked (s halves until no row has one). The colours depend only on the
// positions, so the result is the same on any number of ranks.

#include <perideal/base/input.h>
#include <perideal/discretization/point_cloud.h>
#include <perideal/neighborhood/bonds.h>
#include <perideal/material/tangent_rows.h>

#include <deal.II/base/index_set.h>
#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

#include <functional>
#include <vector>

namespace perideal
{
  using VectorType = dealii::LinearAlgebra::distributed::Vector<double>;

  class Tangent
  {
  public:
    /// The sparsity for a coupling of @p hops bonds (1 or 2). Collective.
    void
    reinit(const PointCloud &cloud, const Bonds &bonds, const unsigned int hops, const MPI_Comm comm);

    /// No matrix: only the 3x3 diagonal blocks, for the matrix-free
    /// solver's block-Jacobi preconditioner (9 doubles per point). Collective.
    void
    reinit_diagonal(const PointCloud &cloud, const unsigned int hops, const MPI_Comm comm);

    /// After reinit_diagonal() and an assembly: the inverse of every owned
    /// point's diagonal block (plus @p mass per owned DoF, may be empty;
    /// identity rows and columns at constrained DoFs). Collective.
    void
    finish_diagonal(const std::vector<double> &mass, std::vector<double> &inverse);

    /// Zeroes the matrix and returns the rows to add to. @p constrained: per
    /// local degree of freedom (owned and ghost entries of the cloud's vector
    /// partitioner), 1 if prescribed.
    TangentRows &
    begin(const std::vector<std::uint8_t> &constrained);

    /// Central differences of @p evaluate (which fills @p force from @p u,
    /// ghosts included, for the owned points) into the owned rows; @p u is
    /// perturbed by @p epsilon and restored. Collective; 6 evaluations per
    /// colour.
    void
    add_finite_differences(VectorType                  &u,
                           const VectorType            &force,
                           const std::function<void()> &evaluate,
                           const double                 epsilon,
                           const double                 reach);

    /// Adds @p values (per owned degree of freedom) to the diagonal of the
    /// free rows (Newmark's mass term).
    void
    add_to_diagonal(const std::vector<double> &values);

    /// Compresses and puts @p diagonal (0: the mean diagonal of the free
    /// rows) on the rows of constrained degrees of freedom. Collective.
    void
    finish(double diagonal = 0);

    dealii::TrilinosWrappers::SparseMatrix matrix;
    dealii::IndexSet                       owned; // owned degrees of freedom
    unsigned int                           hops = 0;
    unsigned int                           n_colours = 0; // of the last finite-difference tangent

    std::size_t
    memory_consumption() const;

  private:
    const PointCloud               *cloud = nullptr;
    MPI_Comm                        comm;
    std::vector<std::uint8_t>       constrained; // per local dof
    TangentRows                     rows;
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> block_partitioner; // diagonal only
  };
} // namespace perideal
