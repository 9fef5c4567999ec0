// Each bond once: the tails of the families (bond_pairs.h).

#include <perideal/neighborhood/bond_pairs.h>

#include <deal.II/base/exceptions.h>

#include <algorithm>

namespace perideal
{
  using namespace dealii;

  void
  BondPairs::reinit(const PointCloud &cloud, const Bonds &bonds, const std::vector<unsigned int> &points,
                    const unsigned int block_)
  {
    block   = block_;
    n_owned = cloud.n_owned();
    list    = points.data();
    upper.resize(points.size());
    head_end.assign(points.size(), 0);
    mixed.resize(points.size());
    std::size_t longest_tail = 0;
    for (std::size_t k = 0; k < points.size(); ++k)
      {
        const unsigned int i     = points[k];
        const std::size_t  first = bonds.offsets[i], last = bonds.offsets[i + 1];
        // No point bonds to an extra point (force blending's node points;
        // find_families()): its family is one-sided, so it takes every bond
        // for itself alone.
        if (cloud.is_extra(i))
          {
            upper[k] = static_cast<unsigned int>(last - first);
            mixed[k] = one_sided;
            continue;
          }
        std::size_t b = first;
        while (b < last && cloud.key[bonds.neighbor[b]] < cloud.key[i])
          ++b;
        upper[k]         = static_cast<unsigned int>(b - first);
        bool outside     = false;
        bool sorted_tail = true;
        for (std::size_t c = first; c < last; ++c)
          {
            const unsigned int j = bonds.neighbor[c];
            const bool         out = !listed(j, cloud.block.data());
            outside |= out;
            sorted_tail &= (c < b) == (cloud.key[j] < cloud.key[i]);
            if (out && c < b)
              head_end[k] = static_cast<unsigned int>(c + 1 - first);
          }
        // find_families() sorts each family by key and filters keep the
        // order: a tail that is not the larger keys would evaluate some
        // bonds twice and others never.
        AssertThrow(sorted_tail, ExcInternalError());
        mixed[k]     = outside ? reaches_outside : inside;
        longest_tail = std::max<std::size_t>(longest_tail, last - b);
      }
    tail_before.assign(longest_tail, 0);
  }

  void
  BondPairs::clear()
  {
    upper.clear();
    head_end.clear();
    mixed.clear();
    tail_before.clear();
    list = nullptr;
  }

  void
  BondPairs::break_other_halves(const PointCloud &cloud, const Bonds &bonds, const unsigned int i,
                                const std::size_t tail, const std::size_t last, std::uint8_t *broken,
                                const std::uint8_t *before) const
  {
    for (std::size_t b = tail; b < last; ++b)
      {
        const unsigned int j = bonds.neighbor[b];
        if (broken[b] != 0 && before[b - tail] == 0 && listed(j, cloud.block.data()))
          broken[reverse(cloud, bonds, i, j)] = 1;
      }
  }

  std::size_t
  BondPairs::reverse(const PointCloud &cloud, const Bonds &bonds, const unsigned int i, const unsigned int j)
  {
    const unsigned int *first = bonds.neighbor.data() + bonds.offsets[j];
    const unsigned int *last  = bonds.neighbor.data() + bonds.offsets[j + 1];
    const unsigned int *it    = std::lower_bound(first, last, i, [&](const unsigned int a, const unsigned int target) {
      return cloud.key[a] < cloud.key[target];
    });
    AssertThrow(it != last && *it == i, ExcInternalError());
    return it - bonds.neighbor.data();
  }
} // namespace perideal
