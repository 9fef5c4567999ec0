#include <perideal/base/memory.h>

#include <fstream>
#include <string>

namespace perideal
{
  namespace
  {
    /// A "Key: value kB" line of /proc/self/status, in bytes (0 if absent).
    double
    status_bytes(const std::string &key)
    {
      std::ifstream status("/proc/self/status");
      std::string   word;
      while (status >> word)
        {
          if (word == key)
            {
              double kb = 0;
              status >> kb;
              return 1024.0 * kb;
            }
          status.ignore(1 << 20, '\n');
        }
      return 0;
    }
  } // namespace

  double
  peak_memory_bytes()
  {
    // VmHWM: the high-water mark of this process image's resident memory
    // (getrusage's ru_maxrss may carry over the image before exec).
    return status_bytes("VmHWM:");
  }

  double
  resident_memory_bytes()
  {
    return status_bytes("VmRSS:");
  }

  double
  peak_memory_bytes_sum(const MPI_Comm comm)
  {
    return dealii::Utilities::MPI::sum(peak_memory_bytes(), comm);
  }
} // namespace perideal
