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

// ------------------------------------------------------- memory available

#include <deal.II/base/utilities.h>

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace perideal
{
  namespace
  {
    /// The first number of a file (0 if it cannot be read); "max": +inf.
    double
    file_number(const std::string &file, bool &found)
    {
      std::ifstream in(file);
      std::string   word;
      found = false;
      if (!(in >> word))
        return 0;
      found = true;
      if (word == "max")
        return std::numeric_limits<double>::infinity();
      try
        {
          return std::stod(word);
        }
      catch (...)
        {
          found = false;
          return 0;
        }
    }

    /// The value of "key value" in a file like memory.stat or meminfo (0 if absent).
    double
    keyed_number(const std::string &file, const std::string &key)
    {
      std::ifstream in(file);
      std::string   word;
      while (in >> word)
        {
          if (word == key)
            {
              double v = 0;
              in >> v;
              return v;
            }
          in.ignore(1 << 20, '\n');
        }
      return 0;
    }

    /// This process's cgroup path for a controller ("" for v2's single hierarchy).
    std::string
    cgroup_path(const std::string &controller)
    {
      std::ifstream in("/proc/self/cgroup");
      std::string   line;
      while (std::getline(in, line))
        {
          // id:controllers:path
          const auto a = line.find(':'), b = line.find(':', a + 1);
          if (a == std::string::npos || b == std::string::npos)
            continue;
          const std::string list = line.substr(a + 1, b - a - 1);
          if ((controller.empty() && list.empty()) ||
              (!controller.empty() && ("," + list + ",").find("," + controller + ",") != std::string::npos))
            return line.substr(b + 1);
        }
      return "";
    }

    /// The memory still allowed by the cgroup limit (+inf without one): the
    /// limit minus the usage, plus the page cache the kernel reclaims first.
    /// Checked in this process's cgroup and its parents (v2 and v1).
    double
    cgroup_remaining(double &limit)
    {
      limit            = std::numeric_limits<double>::infinity();
      double remaining = limit;
      const auto check = [&](const std::string &dir, const bool v2) {
        bool         found = false, found_usage = false;
        const double max   = file_number(dir + (v2 ? "/memory.max" : "/memory.limit_in_bytes"), found);
        if (!found || !(max < 1e18)) // v1 writes about 2^63 for none
          return;
        const double usage = file_number(dir + (v2 ? "/memory.current" : "/memory.usage_in_bytes"), found_usage);
        const double cache = keyed_number(dir + "/memory.stat", v2 ? "file" : "total_cache");
        if (max < limit)
          limit = max;
        remaining = std::min(remaining, std::max(0.0, max - usage + cache));
      };
      for (const bool v2 : {true, false})
        {
          const std::string root = v2 ? "/sys/fs/cgroup" : "/sys/fs/cgroup/memory";
          std::string       path = cgroup_path(v2 ? "" : "memory");
          // The own cgroup and its parents, as far as they are visible.
          while (true)
            {
              check(root + (path == "/" ? std::string() : path), v2);
              if (path.empty() || path == "/")
                break;
              path = path.substr(0, path.rfind('/'));
              if (path.empty())
                path = "/";
            }
          if (v2)
            check("/sys/fs/cgroup/unified", true);
        }
      return remaining;
    }

    std::string
    gib(const double bytes)
    {
      std::ostringstream s;
      s.precision(bytes < 1024.0 * 1024 * 1024 * 100 ? 3 : 4);
      s << bytes / (1024.0 * 1024 * 1024) << " GiB";
      return s.str();
    }
  } // namespace

  AvailableMemory
  available_memory(const MPI_Comm comm)
  {
    // The ranks that share this node's memory.
    MPI_Comm node;
    MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
    int on_node = 1;
    MPI_Comm_size(node, &on_node);
    MPI_Comm_free(&node);

    const double inf = std::numeric_limits<double>::infinity();
    // Per rank: each source's share, the smallest wins.
    double      best = inf;
    std::string why;
    const auto  take = [&](const double bytes, const std::string &text) {
      if (bytes < best)
        {
          best = bytes;
          why  = text;
        }
    };
    const std::string shared = on_node > 1 ? " shared by the " + std::to_string(on_node) + " ranks on the node" : "";

    const double mem_available = 1024.0 * keyed_number("/proc/meminfo", "MemAvailable:");
    if (mem_available > 0)
      take(mem_available / on_node, "MemAvailable of /proc/meminfo " + gib(mem_available) + shared);

    double       cgroup_limit = inf;
    const double cgroup       = cgroup_remaining(cgroup_limit);
    if (cgroup < inf)
      take(cgroup / on_node, "the cgroup memory limit " + gib(cgroup_limit) + ", " + gib(cgroup) + " free" + shared);

    struct rlimit limit;
    if (getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
      {
        const double cap = double(limit.rlim_cur);
        take(std::max(0.0, cap - status_bytes("VmSize:")),
             "RLIMIT_AS (ulimit -v) " + gib(cap) + " per process, " + gib(status_bytes("VmSize:")) +
               " of it mapped at start");
      }
    if (getrlimit(RLIMIT_DATA, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
      {
        const double cap = double(limit.rlim_cur);
        take(std::max(0.0, cap - status_bytes("VmData:")),
             "RLIMIT_DATA (ulimit -d) " + gib(cap) + " per process, " + gib(status_bytes("VmData:")) +
               " of it in use at start");
      }

    AvailableMemory result;
    result.ranks_on_node = dealii::Utilities::MPI::max(static_cast<unsigned int>(on_node), comm);
    // The tightest rank decides for all (every rank gets its share of the scene).
    const double smallest = dealii::Utilities::MPI::min(best, comm);
    const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(comm);
    const unsigned int owner = dealii::Utilities::MPI::min(best == smallest ? rank : ~0u, comm);
    result.bytes_per_rank = smallest;
    // The reason as the tightest rank sees it.
    std::vector<char> text(why.begin(), why.end());
    unsigned int      length = dealii::Utilities::MPI::max(rank == owner ? static_cast<unsigned int>(text.size()) : 0u, comm);
    text.resize(length);
    MPI_Bcast(text.data(), length, MPI_CHAR, owner, comm);
    result.limited_by = std::string(text.begin(), text.end());
    return result;
  }
} // namespace perideal
