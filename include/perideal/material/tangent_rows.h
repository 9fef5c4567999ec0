#pragma once
// What a material writes its tangent into (Material::add_tangent): 3x3 blocks
// of the stiffness K = -dR/du, R_i = V_i f_i, by rows of local points. Kept
// apart from the matrix (solver/tangent.h) so that a material sees neither
// Trilinos nor MPI.

#include <cstddef>
#include <vector>

namespace perideal
{
  class TangentRows
  {
  public:
    /// Adds blocks[9k .. 9k+9) (row-major, 3x3) to the rows of local point
    /// @p row (owned or ghost) at the columns of local point cols[k], k < n.
    /// The pair (row, cols[k]) must be in the tangent's sparsity (a point's
    /// family, and for 2 hops its neighbors' rows with its family's columns).
    /// Rows and columns of constrained degrees of freedom are left out when
    /// the blocks go into the matrix (the solver puts identity rows there).
    void
    add(const unsigned int row, const unsigned int *cols, const double *blocks, const unsigned int n);

  private:
    friend class Tangent;
    // The blocks accumulate here, one 3x3 block per (row point, column
    // point) of the sparsity, and go into the Trilinos matrix once per row
    // when the assembly finishes: a state-based material adds to every
    // block of a row about once per neighbor, and Trilinos' own insertion
    // costs far more than an addition here.
    std::vector<unsigned int> row_of; // per local point: its row here, or -1
    std::vector<std::size_t>  start;  // per row: its first block
    std::vector<unsigned int> column; // per block: local point, ascending in a row
    std::vector<double>       value;  // 9 per block
    bool                      used          = false;
    bool                      diagonal_only = false; // keep only the blocks (p, p)
  };
} // namespace perideal
