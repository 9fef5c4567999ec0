#pragma once
#include <deal.II/base/mpi.h>

namespace perideal
{
  /// Peak resident memory of this process in bytes (VmHWM).
  double
  peak_memory_bytes();

  /// Peak resident memory summed over all ranks of @p comm, in bytes.
  /// Resident memory of this process now, in bytes (VmRSS).
  double
  resident_memory_bytes();

  double
  peak_memory_bytes_sum(const MPI_Comm comm);
} // namespace perideal
