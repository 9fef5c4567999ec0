#pragma once
// The interpolation of a finite element field at points inside its cells, and
// its transpose: u_k = sum_a N_a(x_k) U_a (the matrix Pi), F_a += sum_k N_a(x_k)
// f_k (Pi^T). In the FE-PD coupling (doc/coupling.md) the points are the
// virtual points in FE cells: their displacement comes from the FE field and
// the bond forces on them go back to the FE nodes, action = reaction.
// Since the shape functions sum to one, Pi^T keeps the sum of the forces
// (momentum) and Pi reproduces every field the element reproduces.
// Stored as CSR over the components of the points of locally owned cells:
// per point and component the weights and DoF indices of the nodes; a node
// constrained by hanging-node constraints is replaced by its masters (Pi C),
// so that Pi^T returns the forces to DoFs that carry equations.

#include <perideal/base/input.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <utility>
#include <vector>

namespace perideal
{
  class PointInterpolation
  {
  public:
    using VectorType = dealii::LinearAlgebra::distributed::Vector<double>;

    /// @p points: positions inside locally owned cells of @p dof_handler,
    /// whose element is an FESystem of dim equal scalar Lagrange elements.
    /// The mapping is Q1 (the cells' vertices). With @p constraints
    /// (homogeneous, e.g. hanging nodes; locally relevant lines), a
    /// constrained DoF is replaced by its masters. With @p partitioner (that
    /// of the vectors interpolate() and add_transpose() will get), the DoFs
    /// are stored as local indices: no index translation per step.
    void
    reinit(const dealii::DoFHandler<dim>                                                    &dof_handler,
           const std::vector<std::pair<dealii::DoFHandler<dim>::active_cell_iterator, dealii::Point<dim>>> &points,
           const dealii::AffineConstraints<double>                                         *constraints = nullptr,
           const std::shared_ptr<const dealii::Utilities::MPI::Partitioner>                &partitioner = nullptr);

    unsigned int
    n_points() const
    {
      return (offsets.size() - 1) / dim;
    }

    /// u[dim k + c] = sum_a N_a(x_k) U_{a,c}; @p U with its ghost values
    /// (the DoFs of the cells the points lie in) up to date.
    void
    interpolate(const VectorType &U, std::vector<double> &u) const;

    /// F_{a,c} += sum_k N_a(x_k) f[dim k + c] into the owned and ghost
    /// entries of @p F; the caller compresses with VectorOperation::add.
    void
    add_transpose(const std::vector<double> &f, VectorType &F) const;

    /// Calls @p f(row, dof, weight) for every entry of Pi: row = dim k + c
    /// for point k and component c, dof as stored (local with a partitioner).
    template <typename Function>
    void
    for_each_entry(const Function &f) const
    {
      for (std::size_t k = 0; k + 1 < offsets.size(); ++k)
        for (std::size_t e = offsets[k]; e < offsets[k + 1]; ++e)
          f(k, dofs[e], weight[e]);
    }

  private:
    std::vector<std::size_t>                     offsets{0}; // per point and component, into weight and dofs
    std::vector<double>                          weight;     // N_a(x_k) (times the constraint's weight)
    std::vector<dealii::types::global_dof_index> dofs;       // global, or local with a partitioner
    bool                                         local = false;
  };
} // namespace perideal
