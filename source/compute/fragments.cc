// Fragments: the connected components of the intact bonds, across ranks
// (compute/fragments.h).

#include <perideal/compute/fragments.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    /// Union-find over local point indices, with path halving.
    struct DisjointSets
    {
      std::vector<unsigned int> parent;

      explicit DisjointSets(const unsigned int n)
        : parent(n)
      {
        std::iota(parent.begin(), parent.end(), 0u);
      }
      unsigned int
      find(unsigned int k)
      {
        while (parent[k] != k)
          k = parent[k] = parent[parent[k]];
        return k;
      }
      void
      unite(const unsigned int a, const unsigned int b)
      {
        const unsigned int ra = find(a), rb = find(b);
        if (ra != rb)
          parent[std::max(ra, rb)] = std::min(ra, rb);
      }
    };

    // What a rank sends rank 0 per fragment it holds points of.
    constexpr unsigned int record_size = 7; // label, points, mass, momentum (3), kinetic energy
  } // namespace

  Fragments
  find_fragments(const PointCloud &cloud, const Bonds &bonds, const std::vector<std::uint8_t> &broken,
                 const std::vector<Block> &blocks, const std::vector<double> &mass_density, const VectorType &velocity,
                 const MPI_Comm comm)
  {
    const unsigned int n = cloud.n_owned(), n_local = cloud.n_local();
    DisjointSets       sets(n_local);
    for (unsigned int i = 0; i < n; ++i)
      for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
        if (broken.empty() || !broken[b])
          sets.unite(i, bonds.neighbor[b]);

    // Labels: first the point's own global index, a rigid block's smallest
    // over the whole body (one piece however its points are spread).
    VectorType label(cloud.scalar_partitioner);
    for (unsigned int i = 0; i < n; ++i)
      label.local_element(i) = double(cloud.gid[i]);
    for (const Block &block : blocks)
      if (block.rigid)
        {
          double smallest = std::numeric_limits<double>::max();
          for (const unsigned int i : block.points)
            smallest = std::min(smallest, double(cloud.gid[i]));
          smallest = Utilities::MPI::min(smallest, comm);
          for (const unsigned int i : block.points)
            {
              label.local_element(i) = smallest;
              sets.unite(i, block.points.front());
            }
        }
    label.update_ghost_values();

    // Each component takes the smallest label of its points (the ghosts'
    // labels are their owners' components'), until no label changes.
    std::vector<double> smallest(n_local);
    for (;;)
      {
        std::fill(smallest.begin(), smallest.end(), std::numeric_limits<double>::max());
        for (unsigned int k = 0; k < n_local; ++k)
          {
            const unsigned int root = sets.find(k);
            smallest[root]          = std::min(smallest[root], label.local_element(k));
          }
        unsigned int changed = 0;
        for (unsigned int i = 0; i < n; ++i)
          {
            const double m = smallest[sets.find(i)];
            if (m < label.local_element(i))
              {
                label.local_element(i) = m;
                changed                = 1;
              }
          }
        label.update_ghost_values();
        if (Utilities::MPI::max(changed, comm) == 0)
          break;
      }

    // Each rank's share of every fragment, summed on rank 0.
    std::map<double, Fragments::Row> local;
    for (unsigned int i = 0; i < n; ++i)
      if (mass_density[i] > 0)
        {
          Fragments::Row &row = local[label.local_element(i)];
          const double    m   = mass_density[i] * cloud.volume[i];
          double          v2  = 0;
          row.points += 1;
          row.mass += m;
          for (unsigned int d = 0; d < dim; ++d)
            {
              const double v = velocity.local_element(dim * i + d);
              row.momentum[d] += m * v;
              v2 += v * v;
            }
          row.kinetic_energy += 0.5 * m * v2;
        }
    std::vector<double> records;
    records.reserve(record_size * local.size());
    for (const auto &[l, row] : local)
      records.insert(records.end(), {l, row.points, row.mass, row.momentum[0], row.momentum[1], row.momentum[2],
                                     row.kinetic_energy});
    const std::vector<std::vector<double>> gathered = Utilities::MPI::gather(comm, records, 0);

    Fragments           result;
    std::vector<double> labels; // the fragments' smallest point indices, ascending
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::map<double, Fragments::Row> all;
        for (const auto &from : gathered)
          for (std::size_t r = 0; r < from.size(); r += record_size)
            {
              Fragments::Row &row = all[from[r]];
              row.smallest_point  = from[r];
              row.points += from[r + 1];
              row.mass += from[r + 2];
              for (unsigned int d = 0; d < dim; ++d)
                row.momentum[d] += from[r + 3 + d];
              row.kinetic_energy += from[r + 6];
            }
        for (const auto &[l, row] : all)
          {
            labels.push_back(l);
            result.rows.push_back(row);
          }
      }
    labels       = Utilities::MPI::broadcast(comm, labels, 0);
    result.count = labels.size();
    result.number.resize(n);
    for (unsigned int i = 0; i < n; ++i)
      {
        const auto it    = std::lower_bound(labels.begin(), labels.end(), label.local_element(i));
        result.number[i] = it != labels.end() && *it == label.local_element(i) ? double(it - labels.begin()) : -1.0;
      }
    return result;
  }
} // namespace perideal
