// A point cloud as a coarse mesh of cubes, one per point (see point_cubes.h).

#include <perideal/geometry/point_cubes.h>

#include <deal.II/grid/tria_description.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace perideal
{
  using namespace dealii;

  std::vector<unsigned int>
  morton_order(const std::vector<CloudPoint> &points)
  {
    // The Morton key of each point in its bounding box (21 bits per axis).
    Point<dim> lo = points[0].x, hi = points[0].x;
    for (const auto &p : points)
      for (unsigned int d = 0; d < dim; ++d)
        {
          lo[d] = std::min(lo[d], p.x[d]);
          hi[d] = std::max(hi[d], p.x[d]);
        }
    const auto morton = [&](const Point<dim> &x) {
      std::uint64_t key = 0;
      for (unsigned int d = 0; d < dim; ++d)
        {
          const double        span = hi[d] - lo[d];
          const std::uint64_t q =
            span > 0 ? std::min<std::uint64_t>((1u << 21) - 1, std::uint64_t((x[d] - lo[d]) / span * (1u << 21))) : 0;
          for (unsigned int b = 0; b < 21; ++b)
            key |= ((q >> b) & 1u) << (3 * b + d);
        }
      return key;
    };
    std::vector<std::pair<std::uint64_t, unsigned int>> keyed(points.size());
    for (unsigned int i = 0; i < points.size(); ++i)
      keyed[i] = {morton(points[i].x), i};
    std::sort(keyed.begin(), keyed.end());
    std::vector<unsigned int> order(points.size());
    for (unsigned int c = 0; c < order.size(); ++c)
      order[c] = keyed[c].second;
    return order;
  }

  void
  create_point_cubes(Triangulation<dim> &tria, const std::vector<CloudPoint> &points)
  {
    const std::vector<unsigned int> order = morton_order(points);

    // Cubes whose corners coincide to the bit (a lattice of points) share
    // those vertices: the coarse mesh is then connected, as a mesh is.
    // deal.II orders the coarse cells for p4est by their connectivity
    // (SparsityTools::reorder_hierarchical), and cells that share nothing
    // cost it a search each: 10^5 unconnected cubes take 16 s to set up.
    struct Hash
    {
      std::size_t
      operator()(const std::array<double, 3> &x) const
      {
        std::size_t h = 0;
        for (const double c : x)
          h = h * 1000003u ^ std::hash<double>()(c);
        return h;
      }
    };
    std::unordered_map<std::array<double, 3>, unsigned int, Hash> index;
    index.reserve(2 * points.size());
    std::vector<Point<dim>>    vertices;
    std::vector<CellData<dim>> cells(points.size());
    for (unsigned int c = 0; c < order.size(); ++c)
      {
        const CloudPoint &p = points[order[c]];
        const double      h = 0.5 * std::cbrt(p.volume);
        for (unsigned int v = 0; v < 8; ++v)
          {
            // deal.II's vertex order: x fastest, then y, then z.
            const std::array<double, 3> x{
              {p.x[0] + (v & 1 ? h : -h), p.x[1] + (v & 2 ? h : -h), p.x[2] + (v & 4 ? h : -h)}};
            const auto [it, added] = index.emplace(x, vertices.size());
            if (added)
              vertices.emplace_back(x[0], x[1], x[2]);
            cells[c].vertices[v] = it->second;
          }
        cells[c].material_id = p.block;
      }
    tria.create_triangulation(vertices, cells, SubCellData());
  }
} // namespace perideal
