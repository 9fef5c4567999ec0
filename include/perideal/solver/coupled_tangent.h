#pragma once
// The tangent of a run with continuum blocks (doc/coupling.md) for the
// implicit solvers, on its free degrees of freedom only:
//   z = [free DoFs of the real PD points, free DoFs of the FE nodes].
// The PD tangent A (solver/tangent.h) treats the virtual points as points.
// Their displacement is Pi U, so with T: z -> PD DoFs (1 at a free real DoF,
// Pi's weights at a virtual point's, nothing at a prescribed one) and
// S: z -> FE DoFs (1 at a free FE DoF) the coupled energy is
//   E(z) = E_PD(T z) + 1/2 (S z)^T K_FE (S z),
// its residual T^T (V f) - S^T K_FE S z (what ContinuumField::compute_force
// gives at the FE nodes) and its Hessian
//   K = T^T A T + S^T K_FE S:
// symmetric whenever A is (PMB, LPS), no constrained rows, and the same Newton
// and AMG as a PD run. S^T K_FE S is formed once, T^T A T at every assembly
// (EpetraExt's sparse products: the price of the coupling, see describe()).
// Hanging-node DoFs are not unknowns: K_FE is condensed and Pi's rows hold
// their masters; the caller distributes them after an update.
//
// Force blending (doc/coupling.md) has no energy: the PD points keep their
// rows of A, and an FE node of weight alpha takes alpha (M/rho)/V_p times
// its node point's row of A and 1 - alpha times K_FE's,
//   K = N A T + D S^T K_FE S,
// N picking those rows, D = diag(1 - alpha) on the FE unknowns. It is not
// symmetric (GMRES). It is exact where a point's force depends only on its
// own family (PMB, 1 hop); a node point is in no family, so A's rows of a
// 2-hop material (LPS) miss its neighbors' dilatation terms there, and the
// solver then takes K's products from the residual (implicit_solver.h).

#include <perideal/base/input.h>
#include <perideal/continuum/coupling.h>
#include <perideal/continuum/point_interpolation.h>

#include <deal.II/base/index_set.h>
#include <deal.II/base/partitioner.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <memory>
#include <vector>

namespace perideal
{
  class CoupledTangent
  {
  public:
    /// @p pd_free: local PD DoFs (dim i + c, i an owned real point) that are
    /// unknowns; @p fe_free: local FE DoFs (owned, not hanging) that are
    /// unknowns; @p virtual_points: the owned virtual points in Pi's order;
    /// @p pd_owned: the owned PD DoFs (global dim g + c); @p node_rows:
    /// force blending's rows (nullptr: energy blending). Collective.
    void
    reinit(const std::vector<NodeRow>                                      *node_rows,
           const std::vector<unsigned int>                                  &pd_free,
           const std::vector<unsigned int>                                  &fe_free,
           const std::vector<unsigned int>                                  &virtual_points,
           const PointInterpolation                                         &Pi,
           const dealii::IndexSet                                           &pd_owned,
           const std::shared_ptr<const dealii::Utilities::MPI::Partitioner> &fe_partitioner,
           const dealii::TrilinosWrappers::SparseMatrix                     &K_FE,
           const MPI_Comm                                                    comm);

    /// matrix = T^T A T + S^T K_FE S (force blending: N A T + D S^T K_FE S)
    /// for the PD tangent @p A (rows and columns of prescribed PD DoFs are
    /// not read). Collective.
    void
    assemble(const dealii::TrilinosWrappers::SparseMatrix &A);

    /// Adds @p values (one per FE unknown, in fe_dofs' order) to the
    /// diagonal of the assembled matrix (Newmark's mass term). Collective.
    void
    add_to_fe_diagonal(const std::vector<double> &values);

    /// |x.Ky - y.Kx| / (|x| |y| max(|Kx|/|x|, |Ky|/|y|)) for two fixed
    /// pseudo-random vectors (the same on any number of ranks): 0 for a
    /// symmetric K, round-off in practice. Collective.
    double
    symmetry_defect() const;

    std::size_t
    memory_consumption() const;

    dealii::TrilinosWrappers::SparseMatrix matrix;
    dealii::IndexSet                       owned;  // this rank's unknowns, contiguous
    std::vector<unsigned int>              pd_dofs; // per PD unknown: its local PD DoF
    std::vector<unsigned int>              fe_dofs; // per FE unknown (after the PD ones): its local FE DoF

    bool force_blending = false;

  private:
    /// N and D G (above), after G; @p first: this rank's first unknown.
    void
    reinit_force_blending(const std::vector<NodeRow> &node_rows, const dealii::IndexSet &pd_owned,
                          const dealii::types::global_dof_index first);

    MPI_Comm                               comm = MPI_COMM_SELF;
    dealii::TrilinosWrappers::SparseMatrix T, S, G; // G = S^T K_FE S (force blending: D S^T K_FE S)
    dealii::TrilinosWrappers::SparseMatrix N;       // force blending only
  };
} // namespace perideal
