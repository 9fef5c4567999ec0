#include <perideal/neighborhood/bonds.h>

#include <deal.II/base/bounding_box.h>
#include <deal.II/numerics/rtree.h>

#include <algorithm>

namespace perideal
{
  using namespace dealii;

  Bonds
  find_families(PointCloud                &cloud,
                const std::vector<double> &block_horizon,
                const MPI_Comm             comm)
  {
    namespace bgi = boost::geometry::index;

    const unsigned int      n_owned = cloud.n_owned();
    const unsigned int      n_local = cloud.n_local();
    std::vector<Point<dim>> points(n_local);
    for (unsigned int i = 0; i < n_local; ++i)
      points[i] = cloud.position(i);
    const auto tree = pack_rtree_of_indices(points);

    // Reserve for a full interior family (a lattice holds up to ~9% more
    // points than the sphere's volume) so that the bond array, the largest
    // allocation of a run, is allocated once and never copied.
    double expected = 0;
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        const double delta = block_horizon[cloud.block[i]];
        expected += 4.19 * delta * delta * delta / cloud.volume[i];
      }

    Bonds bonds;
    bonds.offsets.resize(n_owned + 1);
    bonds.neighbor.reserve(static_cast<std::size_t>(expected * 1.1) + 16);
    std::vector<bool>         used(n_local, false);
    std::vector<unsigned int> candidates;
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        bonds.offsets[i]    = bonds.neighbor.size();
        const double     delta = block_horizon[cloud.block[i]];
        const double     reach = delta * (1 + horizon_tolerance);
        const Point<dim> x     = points[i];
        Point<dim>       lo = x, hi = x;
        for (unsigned int d = 0; d < dim; ++d)
          lo[d] -= reach, hi[d] += reach;
        candidates.clear();
        tree.query(bgi::intersects(BoundingBox<dim>({lo, hi})),
                   std::back_inserter(candidates));
        const std::size_t begin = bonds.neighbor.size();
        for (const unsigned int j : candidates)
          if (j != i && x.distance_square(points[j]) <= reach * reach)
            {
              bonds.neighbor.push_back(j);
              used[j] = true;
            }
        std::sort(bonds.neighbor.begin() + begin,
                  bonds.neighbor.end(),
                  [&](unsigned int a, unsigned int b) {
                    return cloud.key[a] < cloud.key[b];
                  });
      }
    bonds.offsets[n_owned] = bonds.neighbor.size();

    // Renumbering keeps the relative order of ghosts (ascending global index),
    // which is not the key order; families stay sorted because the new local
    // indices are only relabels of the same points.
    const auto new_index = cloud.finalize_ghosts(used, comm);
    for (auto &j : bonds.neighbor)
      j = new_index[j];
    return bonds;
  }
} // namespace perideal
