#include <perideal/base/memory.h>

#include <fstream>
#include <string>

namespace perideal
{
  double
  peak_memory_bytes()
  {
    // VmHWM: the high-water mark of this process image's resident memory
    // (getrusage's ru_maxrss may carry over the image before exec).
    std::ifstream status("/proc/self/status");
    std::string   key;
    while (status >> key)
      {
        if (key == "VmHWM:")
          {
            double kb = 0;
            status >> kb;
            return 1024.0 * kb;
          }
        status.ignore(1 << 20, '\n');
      }
    return 0;
  }

  double
  resident_memory_bytes()
  {
    std::ifstream status("/proc/self/status");
    std::string   key;
    while (status >> key)
      {
        if (key == "VmRSS:")
          {
            double kb = 0;
            status >> kb;
            return 1024.0 * kb;
          }
        status.ignore(1 << 20, '\n');
      }
    return 0;
  }

  double
  peak_memory_bytes_sum(const MPI_Comm comm)
  {
    return dealii::Utilities::MPI::sum(peak_memory_bytes(), comm);
  }
} // namespace perideal
