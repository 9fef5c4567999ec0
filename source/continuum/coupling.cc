// The coupling of continuum blocks with peridynamic ones (coupling.h,
// doc/coupling.md): the FE field, the virtual points, Pi and Pi^T.

#include <perideal/continuum/coupling.h>

namespace perideal
{
  using namespace dealii;

  void
  Coupling::setup(const Discretization &discretization, const MPI_Comm comm)
  {
    const PointCloud &cloud  = discretization.cloud;
    const auto       &blocks = discretization.blocks;
    const auto       &cell_fe_weight = discretization.cell_fe_weight;
    virtual_points.clear();
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (discretization.is_virtual(i))
        virtual_points.push_back(i);

    continuum.setup(
      discretization.dof_handler,
      [&](const CellIterator &cell) -> const ContinuumModel * {
        // FE cells: the continuum block that claims them.
        return !discretization.is_fe_cell(cell) ? nullptr : blocks[discretization.block_of_cell(cell)].continuum_model.get();
      },
      [&](const CellIterator &cell) { return cell_fe_weight[cell->active_cell_index()]; },
      comm);
    std::vector<std::pair<CellIterator, Point<dim>>> where;
    for (const unsigned int i : virtual_points)
      where.emplace_back(cloud.cell[i], cloud.position(i));
    continuum.set_virtual_points(discretization.dof_handler, where);
    u_virtual.assign(dim * virtual_points.size(), 0.0);
    f_virtual.assign(dim * virtual_points.size(), 0.0);
    node_density.resize(continuum.nodes.size());
    for (unsigned int k = 0; k < continuum.nodes.size(); ++k)
      node_density[k] = blocks[discretization.block_of_cell(continuum.nodes[k].cell)].continuum_model->density();

    force_blending = discretization.force_blending;
    node_points.clear();
    const IndexSet &owned = discretization.dof_handler.locally_owned_dofs();
    for (unsigned int k = 0; k < discretization.node_points.size(); ++k)
      {
        NodePoint          p;
        const unsigned int i = discretization.node_points[k];
        p.point              = i;
        p.alpha              = discretization.node_point_alpha[k];
        for (unsigned int d = 0; d < dim; ++d)
          p.dof[d] = owned.index_within_set(discretization.node_point_dofs[dim * k + d]);
        p.volume = continuum.mass.local_element(p.dof[0]) / blocks[cloud.block[i]].continuum_model->density();
        node_points.push_back(p);
      }
  }

  std::vector<NodeRow>
  Coupling::node_rows(const PointCloud &cloud) const
  {
    std::vector<NodeRow> rows;
    for (const NodePoint &p : node_points)
      for (unsigned int d = 0; d < dim; ++d)
        rows.push_back({p.dof[d], dim * p.point + d, p.alpha, p.alpha * p.volume / cloud.volume[p.point]});
    return rows;
  }

  void
  Coupling::update_virtual_points(VectorType &displacement)
  {
    continuum.U.update_ghost_values();
    continuum.interpolate(u_virtual);
    for (unsigned int k = 0; k < virtual_points.size(); ++k)
      for (unsigned int d = 0; d < dim; ++d)
        displacement.local_element(dim * virtual_points[k] + d) = u_virtual[dim * k + d];
  }

  void
  Coupling::transfer_forces(const PointCloud &cloud, const VectorType &force)
  {
    if (force_blending)
      {
        continuum.compute_force({}, false);
        // Loads (body force, traction) act in full; the PD force density at
        // a node point has none of them.
        const bool loaded = continuum.load.size() > 0;
        for (const NodePoint &p : node_points)
          for (unsigned int d = 0; d < dim; ++d)
            {
              const double load = loaded ? continuum.load.local_element(p.dof[d]) : 0.0;
              double      &F    = continuum.F.local_element(p.dof[d]);
              F = (1 - p.alpha) * (F - load) + p.alpha * p.volume * force.local_element(dim * p.point + d) + load;
            }
        return;
      }
    for (unsigned int k = 0; k < virtual_points.size(); ++k)
      for (unsigned int d = 0; d < dim; ++d)
        f_virtual[dim * k + d] = cloud.volume[virtual_points[k]] * force.local_element(dim * virtual_points[k] + d);
    continuum.compute_force(f_virtual);
  }
} // namespace perideal
