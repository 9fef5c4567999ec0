#include <perideal/neighborhood/bonds.h>

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/mpi.h>
#include <deal.II/numerics/rtree.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <unordered_map>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    struct KeyHash
    {
      std::size_t
      operator()(const PointKey &k) const
      {
        std::size_t h = 0;
        for (const unsigned int v : k)
          h = h * 0x9E3779B97F4A7C15ull + v;
        return h ^ (h >> 29);
      }
    };

    /// The families PreviousFamilies lets the points keep: an owned point
    /// far from every changed place, known before, whose old neighbors are
    /// all here again.
    class KeptFamilies
    {
    public:
      KeptFamilies(const PreviousFamilies *previous, const PointCloud &cloud, const double extra_reach)
        : previous(previous != nullptr && previous->extra_reach == extra_reach ? previous : nullptr)
      {
        if (this->previous == nullptr)
          return;
        changed = pack_rtree(this->previous->changed);
        std::unordered_map<PointKey, unsigned int, KeyHash> local; // key -> new local index
        local.reserve(cloud.n_local());
        for (unsigned int i = 0; i < cloud.n_local(); ++i)
          local.emplace(cloud.key[i], i);
        const std::vector<PointKey> &far = *this->previous->index_keys;
        now.resize(far.size());
        for (std::size_t k = 0; k < far.size(); ++k)
          {
            const auto j = local.find(far[k]);
            now[k]       = j == local.end() ? numbers::invalid_unsigned_int : j->second;
          }
      }

      /// Appends point @p i's old family (new indices) to @p neighbor;
      /// false, and nothing appended, if it has none to keep.
      bool
      append(const PointCloud &cloud, const unsigned int i, const dealii::Point<dim> &x,
             std::vector<unsigned int> &neighbor) const
      {
        if (previous == nullptr)
          return false;
        namespace bgi = boost::geometry::index;
        for (const auto &p : changed | bgi::adaptors::queried(bgi::nearest(x, 1)))
          if (p.distance(x) <= previous->radius)
            return false;
        const unsigned int old = find_by_key(*previous->keys, *previous->order, cloud.key[i]);
        if (old == numbers::invalid_unsigned_int || (previous->complete != nullptr && !(*previous->complete)[old]))
          return false;
        const std::size_t begin = neighbor.size();
        for (std::size_t b = (*previous->offsets)[old]; b < (*previous->offsets)[old + 1]; ++b)
          {
            const unsigned int j = now[(*previous->neighbor_index)[b]];
            if (j == numbers::invalid_unsigned_int)
              {
                neighbor.resize(begin);
                return false;
              }
            neighbor.push_back(j);
          }
        return true;
      }

    private:
      const PreviousFamilies           *previous;
      dealii::RTree<dealii::Point<dim>> changed; // where points changed
      std::vector<unsigned int>         now;     // per index_keys entry: its new local index, or invalid
    };
  } // namespace

  Bonds
  find_families(PointCloud                      &cloud,
                const std::vector<double>       &block_horizon,
                const MPI_Comm                   comm,
                const double                     extra_reach,
                const std::vector<std::uint8_t> &unbonded_block,
                const PreviousFamilies          *previous)
  {
    const auto unbonded = [&](const unsigned int point) {
      return !unbonded_block.empty() && unbonded_block[cloud.block[point]] != 0;
    };
    namespace bgi = boost::geometry::index;

    const unsigned int      n_owned = cloud.n_owned();
    const unsigned int      n_local = cloud.n_local();
    std::vector<Point<dim>> points(n_local);
    for (unsigned int i = 0; i < n_local; ++i)
      points[i] = cloud.position(i);
    const auto tree = pack_rtree_of_indices(points);
    // Each family is sorted by its far ends' keys (the same order on any
    // number of ranks): by each point's place in the key order, an integer.
    std::vector<unsigned int> by_key(n_local), key_rank(n_local);
    for (unsigned int i = 0; i < n_local; ++i)
      by_key[i] = i;
    std::sort(by_key.begin(), by_key.end(), [&](const unsigned int a, const unsigned int b) {
      return cloud.key[a] < cloud.key[b];
    });
    for (unsigned int r = 0; r < n_local; ++r)
      key_rank[by_key[r]] = r;

    // Reserve for a full interior family (a lattice holds up to ~9% more
    // points than the sphere's volume) so that the bond array, the largest
    // allocation of a run, is allocated once and never copied.
    double expected = 0;
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        const double reach = unbonded(i) ? 0 : block_horizon[cloud.block[i]] + extra_reach;
        // No family holds more than the points there are (a horizon that
        // spans the scene would otherwise reserve beyond any memory).
        expected += std::min(4.19 * reach * reach * reach / cloud.volume[i], double(n_local) / 1.1);
      }

    // A bond joins i and j if either family holds the other: within the
    // larger of the two horizons (the same number on both sides).
    std::vector<double> block_reach(block_horizon.size());
    double              largest_reach = 0;
    for (unsigned int b = 0; b < block_horizon.size(); ++b)
      {
        block_reach[b] = block_horizon[b] * (1 + horizon_tolerance) + extra_reach;
        largest_reach  = std::max(largest_reach, block_reach[b]);
      }
    bool different_horizons = false; // a stored bond joins different horizons

    Bonds bonds;
    bonds.block_horizon = block_horizon;
    bonds.offsets.resize(n_owned + 1);
    bonds.neighbor.reserve(static_cast<std::size_t>(expected * 1.1) + 16);
    std::vector<bool>         used(n_local, false);
    std::vector<unsigned int> candidates;
    const KeptFamilies        kept(previous, cloud, extra_reach);
    // Two points at one place give a bond of length 0 (a division by zero in
    // every model): a mesh with duplicated or overlapping cells.
    unsigned int coincident = 0;
    Point<dim>   first_coincident;
    // A periodic direction: a family near one face continues through the
    // opposite one. One period must hold two horizons, or a point would
    // meet another one twice (as itself and as its image).
    const Periodicity &periodic = cloud.periodicity;
    const bool         wrap     = periodic.any();
    if (wrap)
      {
        double largest = 0;
        for (const double delta : block_horizon)
          largest = std::max(largest, delta * (1 + horizon_tolerance) + extra_reach);
        for (unsigned int d = 0; d < dim; ++d)
          if (periodic.length[d] > 0 && !(2 * largest < periodic.length[d]))
            {
              std::ostringstream message;
              message << "Discretization/Periodic directions: the period along " << "xyz"[d] << " ("
                      << periodic.length[d] << ") must exceed twice the reach of a family (the horizon"
                      << (extra_reach > 0 ? " plus the largest cell radius" : "") << ", 2 x " << largest
                      << "): make the box longer or the horizon shorter";
              AssertThrow(false, ExcMessage(message.str()));
            }
      }
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        bonds.offsets[i]    = bonds.neighbor.size();
        if (unbonded(i))
          continue;
        const double     delta   = block_horizon[cloud.block[i]];
        const double     reach_i = block_reach[cloud.block[i]];
        // Search as far as any family that may hold i reaches.
        const double     reach = largest_reach;
        const Point<dim> x     = points[i];
        if (kept.append(cloud, i, x, bonds.neighbor))
          {
            for (std::size_t b = bonds.offsets[i]; b < bonds.neighbor.size(); ++b)
              {
                used[bonds.neighbor[b]] = true;
                different_horizons |= block_reach[cloud.block[bonds.neighbor[b]]] != reach_i;
              }
            bonds.kept.resize(n_owned);
            bonds.kept[i] = 1;
            continue;
          }
        // Coincident: closer than a millionth of the point's own cell size
        // (not of the horizon, which may be far larger than the cells).
        const double same_place = std::min(1e-9 * delta, 1e-6 * std::cbrt(cloud.volume[i]));
        const bool   extra      = cloud.is_extra(i);
        // The search boxes: around x and, near a periodic face, around x
        // moved one period back through it (every combination of faces).
        std::array<std::array<double, 3>, dim> shifts{};
        std::array<unsigned int, dim>          n_shifts{};
        for (unsigned int d = 0; d < dim; ++d)
          {
            n_shifts[d] = 1;
            if (periodic.length[d] > 0 && x[d] + reach > periodic.upper[d])
              shifts[d][n_shifts[d]++] = -periodic.length[d];
            if (periodic.length[d] > 0 && x[d] - reach < periodic.lower[d])
              shifts[d][n_shifts[d]++] = periodic.length[d];
          }
        candidates.clear();
        for (unsigned int a = 0; a < n_shifts[0]; ++a)
          for (unsigned int b = 0; b < n_shifts[1]; ++b)
            for (unsigned int c = 0; c < n_shifts[2]; ++c)
              {
                const Point<dim> center = x + Point<dim>(shifts[0][a], shifts[1][b], shifts[2][c]);
                Point<dim>       lo = center, hi = center;
                for (unsigned int d = 0; d < dim; ++d)
                  lo[d] -= reach, hi[d] += reach;
                tree.query(bgi::intersects(BoundingBox<dim>({lo, hi})), std::back_inserter(candidates));
              }
        const std::size_t begin = bonds.neighbor.size();
        for (const unsigned int j : candidates)
          {
            // No point bonds to an extra point (the PD force of force
            // blending at an FE node), nor it to a point at its own place.
            if (j == i || unbonded(j) || cloud.is_extra(j))
              continue;
            double e[3] = {points[j][0] - x[0], points[j][1] - x[1], points[j][2] - x[2]};
            if (wrap)
              periodic.wrap(e[0], e[1], e[2]);
            const double r2      = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
            const double reach_j = block_reach[cloud.block[j]];
            const double reach_ij = std::max(reach_i, reach_j);
            if (r2 <= reach_ij * reach_ij && !(extra && std::sqrt(r2) <= same_place))
              {
                different_horizons |= reach_j != reach_i;
                if (std::sqrt(r2) <= same_place && coincident++ == 0)
                  first_coincident = x;
                bonds.neighbor.push_back(key_rank[j]);
                used[j] = true;
              }
          }
        std::sort(bonds.neighbor.begin() + begin, bonds.neighbor.end());
        for (auto b = bonds.neighbor.begin() + begin; b != bonds.neighbor.end(); ++b)
          *b = by_key[*b];
      }
    bonds.offsets[n_owned] = bonds.neighbor.size();
    // Which halves are real: j in F(i) and i in F(j), by the same test as
    // above. Set on every rank if any has such a bond, so that every rank
    // runs the same kernels (1 and N ranks agree bit for bit).
    if (Utilities::MPI::max(different_horizons ? 1u : 0u, comm))
      {
        bonds.family.resize(bonds.n_bonds());
        for (unsigned int i = 0; i < n_owned; ++i)
          for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
            {
              const unsigned int j    = bonds.neighbor[b];
              double             e[3] = {points[j][0] - points[i][0], points[j][1] - points[i][1],
                                         points[j][2] - points[i][2]};
              if (wrap)
                periodic.wrap(e[0], e[1], e[2]);
              const double r2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
              const double ri = block_reach[cloud.block[i]], rj = block_reach[cloud.block[j]];
              bonds.family[b] = (r2 <= ri * ri ? Bonds::own_half : 0) | (r2 <= rj * rj ? Bonds::other_half : 0);
            }
      }
    const unsigned int n_coincident = Utilities::MPI::sum(coincident, comm);
    if (n_coincident > 0)
      {
        // Name the point of the lowest rank that has one.
        const unsigned int rank  = Utilities::MPI::this_mpi_process(comm);
        const unsigned int owner = Utilities::MPI::min(coincident > 0 ? rank : numbers::invalid_unsigned_int, comm);
        Point<dim>         p     = rank == owner ? first_coincident : Point<dim>();
        for (unsigned int d = 0; d < dim; ++d)
          p[d] = Utilities::MPI::sum(p[d], comm);
        std::ostringstream where;
        where << p;
        AssertThrow(false,
                    ExcMessage(std::to_string(n_coincident) + " bonds join points at the same place (closer than 1e-6 "
                               "of a cell's size), the first at (" + where.str() + "): the mesh has duplicated or "
                               "overlapping cells"));
      }

    // Renumbering keeps the relative order of ghosts (ascending global index),
    // which is not the key order; families stay sorted because the new local
    // indices are only relabels of the same points.
    const auto new_index = cloud.finalize_ghosts(used, comm);
    for (auto &j : bonds.neighbor)
      j = new_index[j];
    return bonds;
  }
} // namespace perideal
