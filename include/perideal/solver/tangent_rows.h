#pragma once
// What a material writes its tangent into (Material::add_tangent): 3x3 blocks
// of the stiffness K = -dR/du, R_i = V_i f_i, by rows of local points. Kept
// apart from the matrix (solver/tangent.h) so that a material sees neither
// Trilinos nor MPI.

#include <deal.II/base/types.h>

#include <cstdint>
#include <vector>

namespace dealii::TrilinosWrappers
{
  class SparseMatrix;
}

namespace perideal
{
  class TangentRows
  {
  public:
    /// Adds blocks[9k .. 9k+9) (row-major, 3x3) to the rows of local point
    /// @p row (owned or ghost) at the columns of local point cols[k], k < n.
    /// A column may appear once per call. Rows and columns of constrained
    /// degrees of freedom are left out (the solver puts them back as
    /// identity rows).
    void
    add(const unsigned int row, const unsigned int *cols, const double *blocks, const unsigned int n);

  private:
    friend class Tangent;
    dealii::TrilinosWrappers::SparseMatrix           *matrix = nullptr;
    const std::vector<dealii::types::global_dof_index> *gid  = nullptr; // global point index per local point
    const std::vector<std::uint8_t> *constrained = nullptr;             // per local dof: 1 = constrained
    std::vector<dealii::types::global_dof_index> columns;               // scratch, one DoF row
    std::vector<double>                          values;
  };
} // namespace perideal
