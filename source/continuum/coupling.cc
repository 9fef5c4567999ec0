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
        return cell->active_fe_index() == 0 ? nullptr : blocks[discretization.block_of_cell(cell)].continuum_model.get();
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
    for (unsigned int k = 0; k < virtual_points.size(); ++k)
      for (unsigned int d = 0; d < dim; ++d)
        f_virtual[dim * k + d] = cloud.volume[virtual_points[k]] * force.local_element(dim * virtual_points[k] + d);
    continuum.compute_force(f_virtual);
  }
} // namespace perideal
