#include <perideal/continuum/continuum_field.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/hp/fe_values.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

#include <cmath>
#include <algorithm>
#include <map>

namespace perideal
{
  using namespace dealii;

  std::vector<DoFNode>
  owned_nodes(const DoFHandler<dim> &dof_handler, const std::function<bool(const CellIterator &)> &selected)
  {
    const IndexSet                      &owned = dof_handler.locally_owned_dofs();
    const MappingQ1<dim>                 mapping;
    std::vector<bool>                    seen(owned.n_elements(), false);
    std::vector<types::global_dof_index> dofs;
    std::vector<DoFNode>                 nodes;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && (!selected || selected(cell)))
        {
          const auto &fe = cell->get_fe();
          dofs.resize(fe.n_dofs_per_cell());
          cell->get_dof_indices(dofs);
          for (unsigned int i = 0; i < dofs.size(); ++i)
            if (owned.is_element(dofs[i]))
              {
                const unsigned int k = owned.index_within_set(dofs[i]);
                if (!seen[k])
                  {
                    seen[k] = true;
                    nodes.push_back({k, fe.system_to_component_index(i).first,
                                     mapping.transform_unit_to_real_cell(cell, fe.unit_support_point(i)), cell});
                  }
              }
        }
    return nodes;
  }

  void
  ContinuumField::setup(const DoFHandler<dim>                                                &dof_handler,
                        const std::function<const ContinuumModel *(const CellIterator &)>   &model_of,
                        const std::function<double(const CellIterator &)>                    &weight_of,
                        const MPI_Comm                                                        comm_)
  {
    comm                   = comm_;
    const IndexSet &owned  = dof_handler.locally_owned_dofs();
    IndexSet        relevant;
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    partitioner = std::make_shared<Utilities::MPI::Partitioner>(owned, relevant, comm);
    for (VectorType *v : {&U, &V, &F, &mass, &KU})
      v->reinit(partitioner);
    load.reinit(0);

    hanging.clear();
    hanging.reinit(relevant);
    DoFTools::make_hanging_node_constraints(dof_handler, hanging);
    hanging.close();

    TrilinosWrappers::SparsityPattern pattern(owned, owned, relevant, comm);
    DoFTools::make_sparsity_pattern(dof_handler, pattern, hanging, false, Utilities::MPI::this_mpi_process(comm));
    pattern.compress();
    K.reinit(pattern);

    // Gauss p+1 on FE_Q(p) cells; DG0 (peridynamic) cells are skipped.
    const auto          &fe_collection = dof_handler.get_fe_collection();
    hp::QCollection<dim> quadrature;
    for (unsigned int k = 0; k < fe_collection.size(); ++k)
      quadrature.push_back(QGauss<dim>(std::max(1u, fe_collection[k].degree + 1)));
    hp::FEValues<dim> hp_values(fe_collection, quadrature, update_values | update_gradients | update_JxW_values);
    FullMatrix<double>                   cell_matrix;
    Vector<double>                       cell_mass;
    // Cells of the same shape, size, element and model have the same stable
    // step: a box or a locally refined box has a handful.
    std::map<std::vector<double>, double> step_of_shape;
    element_step = std::numeric_limits<double>::max();
    std::vector<types::global_dof_index> dofs;
    n_fe_cells = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const ContinuumModel *model = model_of(cell);
          if (model == nullptr)
            continue;
          ++n_fe_cells;
          hp_values.reinit(cell);
          const FEValues<dim> &fe_values = hp_values.get_present_fe_values();
          const auto          &fe        = cell->get_fe();
          dofs.resize(fe.n_dofs_per_cell());
          cell->get_dof_indices(dofs);
          model->cell_matrix(fe_values, cell_matrix);
          model->cell_lumped_mass(fe_values, cell_mass);
          std::vector<double> shape = model->constants();
          shape.insert(shape.begin(), double(fe.degree));
          for (const unsigned int v : cell->vertex_indices())
            for (unsigned int d = 0; d < dim; ++d)
              shape.push_back(cell->vertex(v)[d] - cell->vertex(0)[d]);
          const auto known = step_of_shape.find(shape);
          const double step = known != step_of_shape.end() ?
                                known->second :
                                (step_of_shape[shape] = LinearElasticity::stable_time_step(cell_matrix, cell_mass));
          element_step = std::min(element_step, step);
          cell_matrix *= weight_of(cell);
          hanging.distribute_local_to_global(cell_matrix, dofs, K);
          hanging.distribute_local_to_global(cell_mass, dofs, mass);
        }
    K.compress(VectorOperation::add);
    mass.compress(VectorOperation::add);
    n_fe_cells = Utilities::MPI::sum(n_fe_cells, comm);

    nodes = owned_nodes(dof_handler, [&](const CellIterator &cell) { return model_of(cell) != nullptr; });
    free.clear();
    for (const Node &node : nodes)
      if (!hanging.is_constrained(owned.nth_index_in_set(node.local)))
        free.push_back(node.local);
    std::sort(free.begin(), free.end());
    const types::global_dof_index n_fe_dofs = nodes.size();
    n_global_dofs = Utilities::MPI::sum(n_fe_dofs, comm);
  }

  void
  ContinuumField::set_virtual_points(const DoFHandler<dim>                                   &dof_handler,
                                     const std::vector<std::pair<CellIterator, Point<dim>>> &points)
  {
    Pi.reinit(dof_handler, points, &hanging, partitioner);
  }

  void
  ContinuumField::compute_force(const std::vector<double> &f_virtual, const bool transpose)
  {
    F = 0;
    if (transpose)
      {
        Pi.add_transpose(f_virtual, F);
        F.compress(VectorOperation::add);
      }
    K.vmult(KU, U);
    const unsigned int n = partitioner->locally_owned_size();
    for (unsigned int k = 0; k < n; ++k)
      F.local_element(k) -= KU.local_element(k);
    if (load.size() > 0)
      for (unsigned int k = 0; k < n; ++k)
        F.local_element(k) += load.local_element(k);
  }

  void
  ContinuumField::add_face_load(const std::vector<std::pair<CellIterator, unsigned int>> &faces,
                                const unsigned int                                       component,
                                const std::function<double(const Point<dim> &)>         &value)
  {
    if (faces.empty())
      return;
    if (!face_values)
      {
        const auto          &fe_collection = faces.front().first->get_dof_handler().get_fe_collection();
        hp::QCollection<dim - 1> quadrature;
        for (unsigned int k = 0; k < fe_collection.size(); ++k)
          quadrature.push_back(QGauss<dim - 1>(std::max(1u, fe_collection[k].degree + 1)));
        face_values = std::make_unique<hp::FEFaceValues<dim>>(fe_collection, quadrature,
                                                              update_values | update_JxW_values);
      }
    Vector<double>                       cell_load;
    std::vector<types::global_dof_index> dofs;
    for (const auto &[cell, face] : faces)
      {
        face_values->reinit(cell, face);
        Tensor<1, dim> t;
        t[component] = value(cell->face(face)->center());
        LinearElasticity::face_traction(face_values->get_present_fe_values(), t, cell_load);
        dofs.resize(cell->get_fe().n_dofs_per_cell());
        cell->get_dof_indices(dofs);
        hanging.distribute_local_to_global(cell_load, dofs, load);
      }
  }

  double
  ContinuumField::stable_time_step() const
  {
    return Utilities::MPI::min(element_step, comm);
  }

  double
  ContinuumField::strain_energy() const
  {
    double e = 0;
    for (const unsigned int k : free)
      e += 0.5 * U.local_element(k) * KU.local_element(k);
    return Utilities::MPI::sum(e, comm);
  }

  double
  ContinuumField::local_kinetic_energy() const
  {
    double e = 0;
    for (const unsigned int k : free)
      e += 0.5 * mass.local_element(k) * V.local_element(k) * V.local_element(k);
    return e;
  }

  double
  ContinuumField::kinetic_energy() const
  {
    return Utilities::MPI::sum(local_kinetic_energy(), comm);
  }
} // namespace perideal
