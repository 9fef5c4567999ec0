#pragma once
#include <deal.II/base/mpi.h>

#include <string>

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

  /// The memory a rank can still allocate, the same on every rank: the
  /// smallest over ranks of MemAvailable (/proc/meminfo) and the free part
  /// of a cgroup limit (memory.max, v1 memory.limit_in_bytes), each shared by
  /// the ranks of the node (MPI_COMM_TYPE_SHARED), and of RLIMIT_AS
  /// (ulimit -v) minus the mapped size and RLIMIT_DATA minus the data size
  /// of the process. Collective.
  struct AvailableMemory
  {
    double       bytes_per_rank = 0; // +inf if nothing could be read
    unsigned int ranks_on_node  = 1; // the most on one node
    std::string  limited_by;         // which of the above, for messages
  };
  AvailableMemory
  available_memory(const MPI_Comm comm);
} // namespace perideal
