#pragma once
#include <deal.II/base/mpi.h>

namespace perideal
{
  /// Peak resident memory of this process in bytes (getrusage).
  double
  peak_memory_bytes();

  /// Peak resident memory summed over all ranks of @p comm, in bytes.
  double
  peak_memory_bytes_sum(const MPI_Comm comm);
} // namespace perideal
