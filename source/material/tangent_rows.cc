// TangentRows (material/tangent_rows.h): the model layer's side of the
// tangent; the matrix that reads it is solver/tangent.cc.

#include <perideal/material/tangent_rows.h>

#include <deal.II/base/exceptions.h>

#include <algorithm>

namespace perideal
{
  using namespace dealii;

  void
  TangentRows::add(const unsigned int row, const unsigned int *cols, const double *blocks, const unsigned int n)
  {
    used                     = true;
    const unsigned int  r    = row_of[row];
    const unsigned int *base = column.data();
    const unsigned int *first = base + start[r], *last = base + start[r + 1];
    for (unsigned int k = 0; k < n; ++k)
      {
        const unsigned int *it = std::lower_bound(first, last, cols[k]);
        if (it == last || *it != cols[k])
          {
            AssertThrow(diagonal_only, ExcInternalError());
            continue;
          }
        double *v = value.data() + 9 * (it - base);
        for (unsigned int q = 0; q < 9; ++q)
          v[q] += blocks[9 * k + q];
      }
  }
} // namespace perideal
