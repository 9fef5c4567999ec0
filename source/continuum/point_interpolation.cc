#include <perideal/continuum/point_interpolation.h>

#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping_q1.h>

namespace perideal
{
  using namespace dealii;

  void
  PointInterpolation::reinit(const DoFHandler<dim>                                                    &dof_handler,
                             const std::vector<std::pair<DoFHandler<dim>::active_cell_iterator, Point<dim>>> &points,
                             const AffineConstraints<double>                                         *constraints,
                             const std::shared_ptr<const Utilities::MPI::Partitioner>                &partitioner)
  {
    (void)dof_handler;
    offsets.assign(1, 0);
    weight.clear();
    dofs.clear();
    const MappingQ1<dim>                 mapping;
    std::vector<types::global_dof_index> cell_dofs;
    const auto add = [&](const types::global_dof_index dof, const double w) {
      if (constraints != nullptr && constraints->is_constrained(dof))
        {
          for (const auto &[master, c] : *constraints->get_constraint_entries(dof))
            {
              weight.push_back(w * c);
              dofs.push_back(master);
            }
        }
      else
        {
          weight.push_back(w);
          dofs.push_back(dof);
        }
    };
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
        for (unsigned int c = 0; c < dim; ++c)
          {
            for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
              {
                const auto [component, a] = fe.system_to_component_index(i);
                if (component == c)
                  add(cell_dofs[i], base.shape_value(a, xi));
              }
            offsets.push_back(weight.size());
          }
      }
    local = partitioner != nullptr;
    if (local)
      for (auto &d : dofs)
        d = partitioner->global_to_local(d);
  }

  void
  PointInterpolation::interpolate(const VectorType &U, std::vector<double> &u) const
  {
    u.resize(offsets.size() - 1);
    for (std::size_t k = 0; k + 1 < offsets.size(); ++k)
      {
        double sum = 0;
        if (local)
          for (std::size_t e = offsets[k]; e < offsets[k + 1]; ++e)
            sum += weight[e] * U.local_element(dofs[e]);
        else
          for (std::size_t e = offsets[k]; e < offsets[k + 1]; ++e)
            sum += weight[e] * U(dofs[e]);
        u[k] = sum;
      }
  }

  void
  PointInterpolation::add_transpose(const std::vector<double> &f, VectorType &F) const
  {
    for (std::size_t k = 0; k + 1 < offsets.size(); ++k)
      for (std::size_t e = offsets[k]; e < offsets[k + 1]; ++e)
        (local ? F.local_element(dofs[e]) : F(dofs[e])) += weight[e] * f[k];
  }
} // namespace perideal
