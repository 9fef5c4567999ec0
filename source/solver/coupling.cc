// The Simulation's side of the FE-PD coupling (doc/coupling.md): which FE
// cells carry virtual points, the energy weights, the FE field at the
// virtual points and the FE nodes of the boundary conditions.

#include <perideal/solver/simulation.h>

#include <deal.II/numerics/rtree.h>

#include <cmath>

namespace perideal
{
  using namespace dealii;
  namespace bgi = boost::geometry::index;

  void
  Simulation::build_coupled_cloud(const std::function<int(const CellIterator &)> &block_of, const double max_horizon)
  {
    // The PD points within reach of this rank's FE cells: one probe point per
    // FE cell makes the ghost exchange bring them.
    double largest_cell = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && cell->active_fe_index() > 0)
        largest_cell = std::max(largest_cell, cell->diameter());
    largest_cell         = Utilities::MPI::max(largest_cell, comm);
    const int probe      = blocks.size();
    const double reach   = (1 + blending_width) * max_horizon + largest_cell;
    PointCloud   nearby;
    nearby.build(dof_handler,
                 [&](const CellIterator &cell) -> int {
                   const int b = block_of(cell);
                   return b < 0 ? -1 : blocks[b].continuum ? probe : b;
                 },
                 reach, comm);
    std::vector<std::pair<Point<dim>, unsigned int>> pd;
    for (unsigned int i = 0; i < nearby.n_local(); ++i)
      if (nearby.block[i] != probe)
        pd.emplace_back(nearby.position(i), i);
    const auto tree = pack_rtree(pd);

    // Distance to the interface: to the nearest PD point less half its
    // spacing; alpha falls from 1 to 0 over the band (a step without one).
    struct Nearest
    {
      double distance, band, horizon, volume; // volume: of the nearest PD point
    };
    const auto nearest = [&](const Point<dim> &x) -> Nearest {
      for (const auto &p : tree | bgi::adaptors::queried(bgi::nearest(x, 1)))
        {
          const unsigned int i = p.second;
          const double       h = blocks[nearby.block[i]].horizon;
          return {std::max(0.0, x.distance(p.first) - 0.5 * std::cbrt(nearby.volume[i])), blending_width * h, h,
                  nearby.volume[i]};
        }
      return {std::numeric_limits<double>::max(), 0, 0, 1};
    };
    const auto alpha = [](const Nearest &n) {
      return n.band > 0 ? std::max(0.0, 1 - n.distance / n.band) : 0.0;
    };

    cell_fe_weight.assign(triangulation.n_active_cells(), 1.0);
    cell_virtual.assign(triangulation.n_active_cells(), 0);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && cell->active_fe_index() > 0)
        {
          const Nearest n = nearest(cell->center());
          cell_fe_weight[cell->active_cell_index()] = 1 - alpha(n);
          // Virtual points serve up to a horizon beyond the band, at about
          // the nearest PD point's spacing (auto levels).
          if (n.distance - 0.5 * cell->diameter() <= (n.band + n.horizon) * (1 + 1e-9))
            {
              const double ratio  = std::cbrt(cell->measure() / n.volume);
              const int    levels = virtual_point_levels >= 0 ? virtual_point_levels :
                                                                std::max(0, int(std::lround(std::log2(ratio))));
              cell_virtual[cell->active_cell_index()] = 1 + levels;
            }
        }

    cloud.build(dof_handler,
                [&](const CellIterator &cell) -> int {
                  const int b = block_of(cell);
                  return b >= 0 && blocks[b].continuum && !cell_virtual[cell->active_cell_index()] ? -1 : b;
                },
                max_horizon, comm,
                [&](const CellIterator &cell) -> unsigned int {
                  return cell->active_fe_index() > 0 ? cell_virtual[cell->active_cell_index()] - 1 : 0;
                },
                scene.partial_volumes);
    point_alpha.assign(cloud.n_owned(), 1.0);
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (blocks[cloud.block[i]].continuum)
        point_alpha[i] = alpha(nearest(cloud.position(i)));
  }

  void
  Simulation::drop_unweighted_bonds()
  {
    VectorType alpha(cloud.scalar_partitioner);
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      alpha.local_element(i) = point_alpha[i];
    alpha.update_ghost_values();
    bonds.keep_if(cloud.n_owned(), [&](const unsigned int i, const unsigned int j) {
      return point_alpha[i] > 0 || alpha.local_element(j) > 0;
    });
  }

  void
  Simulation::setup_continuum()
  {
    virtual_points.clear();
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (is_virtual(i))
        virtual_points.push_back(i);

    continuum = std::make_unique<ContinuumField>();
    continuum->setup(
      dof_handler,
      [&](const CellIterator &cell) -> const LinearElasticity * {
        // FE cells: the continuum block that claims them.
        return cell->active_fe_index() == 0 ? nullptr : blocks[block_of_cell(cell)].elasticity.get();
      },
      [&](const CellIterator &cell) { return cell_fe_weight[cell->active_cell_index()]; },
      comm);
    std::vector<std::pair<CellIterator, Point<dim>>> where;
    for (const unsigned int i : virtual_points)
      where.emplace_back(cloud.cell[i], cloud.position(i));
    continuum->set_virtual_points(dof_handler, where);
    u_virtual.assign(dim * virtual_points.size(), 0.0);
    f_virtual.assign(dim * virtual_points.size(), 0.0);
    node_density.resize(continuum->nodes.size());
    for (unsigned int k = 0; k < continuum->nodes.size(); ++k)
      node_density[k] = blocks[block_of_cell(continuum->nodes[k].cell)].elasticity->rho;
  }

  std::vector<std::uint8_t>
  Simulation::fe_prescribed_flags() const
  {
    std::vector<std::uint8_t> flags(continuum->U.locally_owned_size(), 0);
    for (const auto &c : node_constraints)
      flags[continuum->nodes[c.node].local] = 1;
    return flags;
  }

  void
  Simulation::update_virtual_points()
  {
    if (!has_continuum)
      return;
    continuum->U.update_ghost_values();
    continuum->interpolate(u_virtual);
    for (unsigned int k = 0; k < virtual_points.size(); ++k)
      for (unsigned int d = 0; d < dim; ++d)
        displacement.local_element(dim * virtual_points[k] + d) = u_virtual[dim * k + d];
  }
} // namespace perideal
