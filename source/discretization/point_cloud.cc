#include <perideal/base/expression.h>
#include <perideal/discretization/point_cloud.h>
#include <perideal/geometry/hexahedron.h>

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/index_set.h>
#include <deal.II/fe/mapping_q1.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <limits>
#include <numeric>
#include <utility>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    // What travels to a neighboring rank for one ghost point, as doubles
    // (all integers involved are exact in a double): gid, x, volume, block,
    // key, and with the cell geometry its 8 vertices.
    constexpr unsigned int record_size = 1 + dim + 1 + 1 + 4;
    constexpr unsigned int vertex_size = 8 * dim;
  } // namespace

  std::uint64_t
  PointCloud::hash(const unsigned int i) const
  {
    std::uint64_t h = 0;
    for (const unsigned int k : key[i])
      h = mix64(h ^ k);
    return h;
  }

  std::vector<boost::signals2::scoped_connection>
  on_mesh_change(const Triangulation<dim> &triangulation, const std::function<void()> &forget)
  {
    std::vector<boost::signals2::scoped_connection> connections;
    connections.emplace_back(triangulation.signals.any_change.connect(forget));
    connections.emplace_back(triangulation.signals.post_distributed_refinement.connect(forget));
    connections.emplace_back(triangulation.signals.post_distributed_repartition.connect(forget));
    connections.emplace_back(triangulation.signals.post_distributed_load.connect(forget));
    return connections;
  }

  std::pair<Point<dim>, double>
  CellGeometry::operator()(const CellIterator &cell)
  {
    const std::size_t n = cell->get_triangulation().n_active_cells();
    if (data.size() != (dim + 1) * n)
      data.assign((dim + 1) * n, std::numeric_limits<double>::quiet_NaN());
    double *entry = &data[(dim + 1) * cell->active_cell_index()];
    if (std::isnan(entry[dim]))
      {
        const Point<dim> x = cell_centroid(cell);
        for (unsigned int d = 0; d < dim; ++d)
          entry[d] = x[d];
        entry[dim] = cell_volume(cell);
      }
    Point<dim> x;
    for (unsigned int d = 0; d < dim; ++d)
      x[d] = entry[d];
    return {x, entry[dim]};
  }

  void
  PointCloud::build(const DoFHandler<dim>                                   &dof_handler,
                    const std::function<int(const CellIterator &)>          &block_of,
                    const double                                             max_horizon,
                    const MPI_Comm                                           comm,
                    const std::function<unsigned int(const CellIterator &)> &levels_of,
                    const bool                                               cell_geometry,
                    const std::vector<ExtraPoint>                           &extra,
                    CellGeometry                                            *geometry)
  {
    const auto centroid_and_volume = [geometry](const CellIterator &c) -> std::pair<Point<dim>, double> {
      return geometry != nullptr ? (*geometry)(c) : std::make_pair(cell_centroid(c), cell_volume(c));
    };
    X.clear();
    volume.clear();
    block.clear();
    key.clear();
    gid.clear();
    cell.clear();
    cell_vertices.clear();
    max_cell_radius = 0;
    const auto add_vertices = [&](const std::array<Point<dim>, 8> &v, const Point<dim> &x) {
      for (const Point<dim> &p : v)
        {
          max_cell_radius = std::max(max_cell_radius, p.distance(x));
          for (unsigned int d = 0; d < dim; ++d)
            cell_vertices.push_back(p[d]);
        }
    };

    for (const auto &c : dof_handler.active_cell_iterators())
      if (c->is_locally_owned())
        {
          const int b = block_of(c);
          if (b < 0)
            continue;
          const unsigned int levels = levels_of ? levels_of(c) : 0;
          if (levels == 0)
            {
              const auto [x, v] = centroid_and_volume(c); // the centroid, as Peridigm places an element's point
              for (unsigned int d = 0; d < dim; ++d)
                X.push_back(x[d]);
              volume.push_back(v);
              block.push_back(b);
              key.push_back(c->id().template to_binary<dim>());
              cell.push_back(c);
              if (cell_geometry)
                {
                  std::array<Point<dim>, 8> v;
                  for (unsigned int k = 0; k < 8; ++k)
                    v[k] = c->vertex(k);
                  add_vertices(v, x);
                }
              continue;
            }
          // The descendants r levels down, in lexicographic order of the
          // lattice; the child index of a hexahedron is ix + 2 iy + 4 iz.
          const unsigned int n          = 1u << levels;
          const double       sub_volume = centroid_and_volume(c).second / std::pow(8.0, levels);
          const CellId       id         = c->id();
          const MappingQ1<dim> mapping;
          const auto         parent     = id.get_child_indices();
          for (unsigned int iz = 0; iz < n; ++iz)
            for (unsigned int iy = 0; iy < n; ++iy)
              for (unsigned int ix = 0; ix < n; ++ix)
                {
                  const Point<dim> xi((ix + 0.5) / n, (iy + 0.5) / n, (iz + 0.5) / n);
                  const Point<dim> x = mapping.transform_unit_to_real_cell(c, xi);
                  for (unsigned int d = 0; d < dim; ++d)
                    X.push_back(x[d]);
                  volume.push_back(sub_volume);
                  block.push_back(b);
                  std::vector<std::uint8_t> path(parent.begin(), parent.end());
                  for (unsigned int l = 0; l < levels; ++l)
                    {
                      const unsigned int bit = levels - 1 - l;
                      path.push_back(((ix >> bit) & 1) + 2 * ((iy >> bit) & 1) + 4 * ((iz >> bit) & 1));
                    }
                  key.push_back(CellId(id.get_coarse_cell_id(), path).template to_binary<dim>());
                  cell.push_back(c);
                  if (cell_geometry)
                    {
                      // The descendant's corners: the Q1 map of the lattice cell's.
                      std::array<Point<dim>, 8> v;
                      for (unsigned int k = 0; k < 8; ++k)
                        v[k] = mapping.transform_unit_to_real_cell(
                          c, Point<dim>(double(ix + (k & 1)) / n, double(iy + ((k >> 1) & 1)) / n,
                                        double(iz + ((k >> 2) & 1)) / n));
                      add_vertices(v, x);
                    }
                }
        }
    for (const ExtraPoint &e : extra)
      {
        for (unsigned int d = 0; d < dim; ++d)
          X.push_back(e.x[d]);
        volume.push_back(e.volume);
        block.push_back(e.block);
        key.push_back(e.key);
        cell.push_back(e.cell);
        if (cell_geometry)
          {
            std::array<Point<dim>, 8> v;
            for (unsigned int k = 0; k < 8; ++k)
              v[k] = e.cell->vertex(k);
            add_vertices(v, e.x);
          }
      }
    n_owned_points = volume.size();
    {
      unsigned long long mine = n_owned_points, before = 0;
      MPI_Exscan(&mine, &before, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, comm);
      first_gid = Utilities::MPI::this_mpi_process(comm) == 0 ? 0 : before;
    }
    n_global_points =
      Utilities::MPI::sum(types::global_dof_index(n_owned_points), comm);
    gid.resize(n_owned_points);
    std::iota(gid.begin(), gid.end(), first_gid);
    if (cell_geometry)
      max_cell_radius = Utilities::MPI::max(max_cell_radius, comm);

    // Nonlocal ghosts: exchange bounding boxes, send every owned point that
    // lies within the horizon of another rank's box (or of its periodic
    // images) to that rank.
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
    const unsigned int my_rank = Utilities::MPI::this_mpi_process(comm);
    if (n_ranks == 1)
      return;
    std::array<double, 2 * dim> box;
    for (unsigned int d = 0; d < dim; ++d)
      {
        box[d]       = std::numeric_limits<double>::max();
        box[dim + d] = -std::numeric_limits<double>::max();
      }
    for (unsigned int i = 0; i < n_owned_points; ++i)
      for (unsigned int d = 0; d < dim; ++d)
        {
          box[d]       = std::min(box[d], X[3 * i + d]);
          box[dim + d] = std::max(box[dim + d], X[3 * i + d]);
        }
    const auto boxes = Utilities::MPI::all_gather(comm, box);

    // A small relative margin keeps points at exactly the horizon.
    const double reach = max_horizon * (1 + 1e-6) + max_cell_radius;
    std::map<unsigned int, std::vector<double>> to_send;
    for (unsigned int r = 0; r < n_ranks; ++r)
      {
        if (r == my_rank || boxes[r][0] > boxes[r][dim])
          continue; // myself, or a rank without points
        std::vector<double> records;
        for (unsigned int i = 0; i < n_owned_points; ++i)
          {
            bool inside = true;
            for (unsigned int d = 0; d < dim && inside; ++d)
              {
                // Where periodic, the point's images one period away count too.
                const double lo = boxes[r][d] - reach, hi = boxes[r][dim + d] + reach, x = X[3 * i + d],
                             L = periodicity.length[d];
                inside = (x >= lo && x <= hi) || (L > 0 && ((x + L >= lo && x + L <= hi) || (x - L >= lo && x - L <= hi)));
              }
            if (inside)
              {
                records.push_back(gid[i]);
                for (unsigned int d = 0; d < dim; ++d)
                  records.push_back(X[3 * i + d]);
                records.push_back(volume[i]);
                records.push_back(block[i]);
                for (const unsigned int k : key[i])
                  records.push_back(k);
                if (cell_geometry)
                  records.insert(records.end(), cell_vertices.begin() + vertex_size * i,
                                 cell_vertices.begin() + vertex_size * (i + 1));
              }
          }
        if (!records.empty())
          to_send[r] = std::move(records);
      }
    const auto received = Utilities::MPI::some_to_some(comm, to_send);
    const unsigned int size = record_size + (cell_geometry ? vertex_size : 0);
    for (const auto &entry : received)
      for (std::size_t r = 0; r < entry.second.size(); r += size)
        {
          const double *p = entry.second.data() + r;
          gid.push_back(static_cast<types::global_dof_index>(p[0]));
          for (unsigned int d = 0; d < dim; ++d)
            X.push_back(p[1 + d]);
          volume.push_back(p[1 + dim]);
          block.push_back(static_cast<unsigned short>(p[2 + dim]));
          PointKey k;
          for (unsigned int c = 0; c < 4; ++c)
            k[c] = static_cast<unsigned int>(p[3 + dim + c]);
          key.push_back(k);
          if (cell_geometry)
            cell_vertices.insert(cell_vertices.end(), p + record_size, p + record_size + vertex_size);
        }
  }

  std::vector<unsigned int>
  PointCloud::finalize_ghosts(const std::vector<bool> &used, const MPI_Comm comm)
  {
    const unsigned int        n_old = volume.size();
    std::vector<unsigned int> ghosts;
    for (unsigned int i = n_owned_points; i < n_old; ++i)
      if (used[i])
        ghosts.push_back(i);
    std::sort(ghosts.begin(), ghosts.end(), [&](unsigned int a, unsigned int b) {
      return gid[a] < gid[b];
    });

    std::vector<unsigned int> new_index(n_old, numbers::invalid_unsigned_int);
    for (unsigned int i = 0; i < n_owned_points; ++i)
      new_index[i] = i;
    for (unsigned int g = 0; g < ghosts.size(); ++g)
      new_index[ghosts[g]] = n_owned_points + g;

    const unsigned int n_new = n_owned_points + ghosts.size();
    std::vector<double>                  X_new(dim * n_new);
    std::vector<double>                  volume_new(n_new);
    std::vector<unsigned short>          block_new(n_new);
    std::vector<PointKey>                key_new(n_new);
    std::vector<types::global_dof_index> gid_new(n_new);
    std::vector<double>                  vertices_new(cell_vertices.empty() ? 0 : vertex_size * n_new);
    for (unsigned int i = 0; i < n_old; ++i)
      if (new_index[i] != numbers::invalid_unsigned_int)
        {
          const unsigned int j = new_index[i];
          for (unsigned int d = 0; d < dim; ++d)
            X_new[dim * j + d] = X[dim * i + d];
          volume_new[j] = volume[i];
          block_new[j]  = block[i];
          key_new[j]    = key[i];
          gid_new[j]    = gid[i];
          if (!vertices_new.empty())
            std::copy(cell_vertices.begin() + vertex_size * i, cell_vertices.begin() + vertex_size * (i + 1),
                      vertices_new.begin() + vertex_size * j);
        }
    X.swap(X_new);
    volume.swap(volume_new);
    block.swap(block_new);
    key.swap(key_new);
    gid.swap(gid_new);
    cell_vertices.swap(vertices_new);

    IndexSet owned(n_global_points), ghost(n_global_points);
    owned.add_range(first_gid, first_gid + n_owned_points);
    for (unsigned int i = n_owned_points; i < n_new; ++i)
      ghost.add_index(gid[i]);
    owned.compress();
    ghost.compress();
    // No points at all (a run of continuum blocks only): deal.II's ghost
    // dictionary cannot partition an empty index space.
    scalar_partitioner = n_global_points == 0 ? std::make_shared<Utilities::MPI::Partitioner>(owned, comm) :
                                                std::make_shared<Utilities::MPI::Partitioner>(owned, ghost, comm);

    IndexSet owned_v(dim * n_global_points), ghost_v(dim * n_global_points);
    owned_v.add_range(dim * first_gid, dim * (first_gid + n_owned_points));
    std::vector<types::global_dof_index> ghost_entries;
    ghost_entries.reserve(dim * (n_new - n_owned_points));
    for (unsigned int i = n_owned_points; i < n_new; ++i)
      for (unsigned int d = 0; d < dim; ++d)
        ghost_entries.push_back(dim * gid[i] + d);
    ghost_v.add_indices(ghost_entries.begin(), ghost_entries.end());
    owned_v.compress();
    ghost_v.compress();
    vector_partitioner = n_global_points == 0 ? std::make_shared<Utilities::MPI::Partitioner>(owned_v, comm) :
                                                std::make_shared<Utilities::MPI::Partitioner>(owned_v, ghost_v, comm);
    return new_index;
  }
} // namespace perideal
