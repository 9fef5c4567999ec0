#include <perideal/base/memory.h>

#include <sys/resource.h>

namespace perideal
{
  double
  peak_memory_bytes()
  {
    rusage usage;
    getrusage(RUSAGE_SELF, &usage);
    return 1024.0 * usage.ru_maxrss; // Linux reports kilobytes
  }

  double
  peak_memory_bytes_sum(const MPI_Comm comm)
  {
    return dealii::Utilities::MPI::sum(peak_memory_bytes(), comm);
  }
} // namespace perideal
