// The size of a scene before it is allocated (Discretization::setup): the
// estimates of perideal/discretization/size_estimate.h for the built-in
// scenes and for a mesh about to be refined.
#include <perideal/discretization/size_estimate.h>
#include <perideal/discretization/discretization.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

namespace perideal
{
  using namespace dealii;

  std::string
  Discretization::horizon_key() const
  {
    const Block *largest = nullptr;
    for (const auto &b : blocks)
      if (!b.continuum && (largest == nullptr || b.horizon > largest->horizon))
        largest = &b;
    if (largest == nullptr || largest->horizon == scene.horizon)
      return "Discretization/Horizon";
    return "Blocks/" + largest->name + "/Horizon";
  }

  void
  Discretization::check_scene_size(const AvailableMemory &available) const
  {
    SceneGeometry::Lattice lattice;
    if (!scene.geometry->lattice(lattice))
      return;
    SizeEstimate                e;
    const std::array<double, 3> &n = lattice.cells, &h = lattice.spacing;
    e.coarse_cells                 = lattice.coarse_cells;
    e.cells = n[0] * n[1] * n[2];

    // Every cell has material id 0: all are points if a peridynamic block
    // without a region claims id 0 before any continuum block could take
    // cells; the bonds with the smallest horizon of the blocks on the way.
    double delta = std::numeric_limits<double>::infinity();
    bool   all   = false;
    for (const auto &b : blocks)
      {
        if (b.continuum)
          break;
        delta = std::min(delta, b.horizon);
        if (b.region.empty() && std::find(b.material_ids.begin(), b.material_ids.end(), 0u) != b.material_ids.end())
          {
            all = true;
            break;
          }
      }
    if (all)
      {
        e.points = e.cells;
        e.bonds  = lattice_pairs(n, h, delta);
      }
    check_size(e, available, Utilities::MPI::n_mpi_processes(comm), "the scene", scene.geometry->cells_key(), horizon_key(),
               dry_run_mode, pcout);
  }

  void
  Discretization::check_mesh_size(const AvailableMemory &available, const std::string &what,
                              const std::string &cells_key, const double descendants) const
  {
    // The cells as they are plus 7 per cell flagged for refinement (p4est's
    // balance may add more); the points likewise from the cells' blocks.
    double owned_cells = 0, owned_points = 0, same_bin_pairs = 0;
    double delta = std::numeric_limits<double>::infinity();
    for (const auto &b : blocks)
      if (!b.continuum)
        delta = std::min(delta, b.horizon);
    // Points surely closer than the horizon: bins of side horizon / 3, and
    // the pairs of points in bins at offsets o with side * |(|o|+1)| <= the
    // horizon (the bin itself and its 18 face and edge neighbours). This
    // rank's own points only: a lower bound.
    const double side = 0.999 * delta / 3;
    struct Hash
    {
      std::size_t
      operator()(const std::array<long long, 3> &k) const
      {
        return std::hash<long long>()(k[0] * 73856093LL ^ k[1] * 19349663LL ^ k[2] * 83492791LL);
      }
    };
    std::unordered_map<std::array<long long, 3>, double, Hash> bins;
    std::array<double, 3> low{{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
                               std::numeric_limits<double>::max()}};
    std::array<double, 3> high{{-low[0], -low[1], -low[2]}};
    const bool            binned = std::isfinite(side) && side > 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const double children = descendants > 0 ? descendants : cell->refine_flag_set() ? 8 : 1;
          const bool   refined  = children > 1;
          owned_cells += children;
          const int b = block_of_cell(cell);
          if (b < 0 || blocks[b].continuum)
            continue;
          owned_points += children;
          const Point<dim> x = cell->center();
          for (unsigned int d = 0; d < dim; ++d)
            low[d] = std::min(low[d], x[d]), high[d] = std::max(high[d], x[d]);
          if (refined && cell->diameter() <= delta)
            same_bin_pairs += children * (children - 1); // the children among themselves
          if (binned && !refined)
            {
              std::array<long long, 3> key;
              bool                     finite = true;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  const double q = std::floor(x[d] / side);
                  finite         = finite && std::abs(q) < 1e15;
                  key[d]         = finite ? static_cast<long long>(q) : 0;
                }
              if (finite)
                bins[key] += 1;
            }
        }
    for (const auto &bin : bins)
      for (int a = -1; a <= 1; ++a)
        for (int b = -1; b <= 1; ++b)
          for (int c = -1; c <= 1; ++c)
            {
              if (a != 0 && b != 0 && c != 0)
                continue; // a corner neighbour may be farther than the horizon
              if (a == 0 && b == 0 && c == 0)
                {
                  same_bin_pairs += bin.second * (bin.second - 1);
                  continue;
                }
              const auto other = bins.find({{bin.first[0] + a, bin.first[1] + b, bin.first[2] + c}});
              if (other != bins.end())
                same_bin_pairs += bin.second * other->second;
            }
    for (unsigned int d = 0; d < dim; ++d)
      {
        low[d]  = Utilities::MPI::min(low[d], comm);
        high[d] = Utilities::MPI::max(high[d], comm);
      }

    SizeEstimate e;
    e.coarse_cells = triangulation.n_cells(0);
    e.cells        = Utilities::MPI::sum(owned_cells, comm);
    e.points       = Utilities::MPI::sum(owned_points, comm);
    e.bonds        = Utilities::MPI::sum(same_bin_pairs, comm);
    // Within one horizon of each other: every pair is a bond.
    double diagonal = 0;
    for (unsigned int d = 0; d < dim; ++d)
      diagonal += (high[d] - low[d]) * (high[d] - low[d]);
    if (e.points > 1 && std::sqrt(diagonal) <= delta)
      e.bonds = e.points * (e.points - 1);
    check_size(e, available, Utilities::MPI::n_mpi_processes(comm), what, cells_key, horizon_key(),
               dry_run_mode, pcout);
  }
} // namespace perideal
