#include <perideal/continuum/point_interpolation.h>

#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping_q1.h>

namespace perideal
{
  using namespace dealii;

  void
  PointInterpolation::reinit(const DoFHandler<dim>                                                    &dof_handler,
                             const std::vector<std::pair<DoFHandler<dim>::active_cell_iterator, Point<dim>>> &points)
  {
    offsets.assign(1, 0);
    shape.clear();
    dofs.clear();
    const MappingQ1<dim>                 mapping;
    std::vector<types::global_dof_index> cell_dofs;
    for (const auto &[cell, x] : points)
      {
        AssertThrow(cell->is_locally_owned(), ExcMessage("PointInterpolation: a point in a cell this rank does not own"));
        const auto &fe = cell->get_fe();
        AssertThrow(fe.n_components() == dim && fe.n_base_elements() == 1 && fe.element_multiplicity(0) == dim,
                    ExcMessage("PointInterpolation needs an FESystem of dim equal scalar elements"));
        const Point<dim> xi = mapping.transform_real_to_unit_cell(cell, x);
        AssertThrow(GeometryInfo<dim>::is_inside_unit_cell(xi, 1e-10),
                    ExcMessage("PointInterpolation: a point outside its cell"));
        cell_dofs.resize(fe.n_dofs_per_cell());
        cell->get_dof_indices(cell_dofs);
        const auto &base = fe.base_element(0);
        // The DoF of node a, component c.
        std::vector<types::global_dof_index> node_dofs(dim * base.n_dofs_per_cell());
        for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
          {
            const auto [c, a] = fe.system_to_component_index(i);
            node_dofs[dim * a + c] = cell_dofs[i];
          }
        for (unsigned int a = 0; a < base.n_dofs_per_cell(); ++a)
          {
            shape.push_back(base.shape_value(a, xi));
            for (unsigned int c = 0; c < dim; ++c)
              dofs.push_back(node_dofs[dim * a + c]);
          }
        offsets.push_back(shape.size());
      }
  }

  void
  PointInterpolation::interpolate(const VectorType &U, std::vector<double> &u) const
  {
    u.assign(dim * n_points(), 0.0);
    for (unsigned int k = 0; k < n_points(); ++k)
      for (std::size_t e = offsets[k]; e < offsets[k + 1]; ++e)
        for (unsigned int c = 0; c < dim; ++c)
          u[dim * k + c] += shape[e] * U(dofs[dim * e + c]);
  }

  void
  PointInterpolation::add_transpose(const std::vector<double> &f, VectorType &F) const
  {
    for (unsigned int k = 0; k < n_points(); ++k)
      for (std::size_t e = offsets[k]; e < offsets[k + 1]; ++e)
        for (unsigned int c = 0; c < dim; ++c)
          F(dofs[dim * e + c]) += shape[e] * f[dim * k + c];
  }
} // namespace perideal
