#include <perideal/continuum/continuum_field.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/hp/fe_values.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>

#include <cmath>
#include <algorithm>
#include <map>
#include <set>

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
    // The components of one support point share its place: mapped once.
    std::vector<Point<dim>>   support;
    std::vector<std::uint8_t> mapped;
    // The owned cells first, then the ghost ones: a DoF this rank owns may
    // lie on ghost FE cells only, where the owned cells beside them have
    // converted (they keep their FE_Q DoFs: Discretization::is_fe_cell()).
    for (const bool owned_cells : {true, false})
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned() == owned_cells && !cell->is_artificial() && (!selected || selected(cell)))
          {
            const auto &fe = cell->get_fe();
            dofs.resize(fe.n_dofs_per_cell());
            cell->get_dof_indices(dofs);
            support.resize(dofs.size());
            mapped.assign(dofs.size(), 0);
            for (unsigned int i = 0; i < dofs.size(); ++i)
              if (owned.is_element(dofs[i]))
                {
                  const unsigned int k = owned.index_within_set(dofs[i]);
                  if (!seen[k])
                    {
                      seen[k]                     = true;
                      const auto [component, base] = fe.system_to_component_index(i);
                      if (!mapped[base])
                        {
                          support[base] = mapping.transform_unit_to_real_cell(cell, fe.unit_support_point(i));
                          mapped[base]  = 1;
                        }
                      nodes.push_back({k, component, support[base], cell});
                    }
                }
          }
    return nodes;
  }

  namespace
  {
    /// What a cell's matrix, lumped mass and stable step depend on: the
    /// element's degree, the model's constants and the vertices relative to
    /// the first, rounded to 1e-10 of the decade of the cell's diameter (the
    /// cells of a box differ in the last bits of their vertices, which would
    /// make each one a new shape; the decade is part of the key, so that
    /// cells alike but of different size differ).
    std::vector<double>
    shape_key(const CellIterator &cell, const ContinuumModel &model)
    {
      std::vector<double> key = model.constants();
      key.insert(key.begin(), double(cell->get_fe().degree));
      const double decade = std::floor(std::log10(cell->diameter()));
      const double grid   = std::pow(10.0, decade - 10);
      key.push_back(decade);
      for (const unsigned int v : cell->vertex_indices())
        for (unsigned int d = 0; d < dim; ++d)
          key.push_back(std::round((cell->vertex(v)[d] - cell->vertex(0)[d]) / grid));
      return key;
    }

    /// f = w A u for a symmetric n x n matrix A (row major), as the sum of
    /// A's rows scaled by w u_j (its rows are its columns): contiguous inner
    /// loops without horizontal sums, which the compiler vectorizes. N: n
    /// when known at compile time, 0 otherwise.
    template <unsigned int N>
    void
    weighted_product(const double *__restrict A, const double *__restrict u, const double w, double *__restrict f,
                     const unsigned int n_runtime)
    {
      const unsigned int n = N > 0 ? N : n_runtime;
      for (unsigned int i = 0; i < n; ++i)
        f[i] = 0;
      for (unsigned int j = 0; j < n; ++j)
        {
          const double *row = A + std::size_t(j) * n;
          const double  s   = w * u[j];
          for (unsigned int i = 0; i < n; ++i)
            f[i] += row[i] * s;
        }
    }
  } // namespace

  void
  ContinuumField::setup(const DoFHandler<dim>                                                &dof_handler,
                        const std::function<const ContinuumModel *(const CellIterator &)>   &model_of,
                        const std::function<double(const CellIterator &)>                    &weight_of,
                        const MPI_Comm                                                        comm_)
  {
    comm                   = comm_;
    dofs_of_cells          = &dof_handler;
    watch_mesh(dof_handler.get_triangulation());
    const IndexSet &owned  = dof_handler.locally_owned_dofs();
    IndexSet        relevant;
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    partitioner = std::make_shared<Utilities::MPI::Partitioner>(owned, relevant, comm);
    for (VectorType *v : {&U, &V, &F, &mass, &KU})
      v->reinit(partitioner);
    load.reinit(0);

    make_hanging_constraints(dof_handler, model_of, relevant);

    by_cell = Utilities::MPI::min(shapes_fit(dof_handler, model_of) ? 1u : 0u, comm) == 1;
    K.clear();
    matrix_from_cells = false;
    if (!by_cell)
      make_matrix();
    collect_cells(dof_handler, model_of, weight_of);
    if (!by_cell)
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
  ContinuumField::make_hanging_constraints(const DoFHandler<dim>                                              &dof_handler,
                                           const std::function<const ContinuumModel *(const CellIterator &)> &model_of,
                                           const IndexSet                                                     &relevant)
  {
    hanging.clear();
    hanging.reinit(relevant);
    AffineConstraints<double> all(relevant);
    DoFTools::make_hanging_node_constraints(dof_handler, all);
    if (all.n_constraints() == 0)
      {
        hanging.close();
        return;
      }
    // deal.II constrains a fine cell's DoFs on the face of a coarser cell
    // that has FE_Q DoFs. A converted cell keeps its FE_Q DoFs (the
    // numbering holds through conversions: Discretization::is_fe_cell()),
    // but as a PD cell it constrains nothing: the fine FE cells' DoFs on its
    // faces stay free, as where a cell was PD (FE_DGQ(0)) from the start.
    std::set<types::global_dof_index>    by_fe, by_pd;
    std::vector<types::global_dof_index> dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial() && model_of(cell) != nullptr)
        for (const unsigned int f : cell->face_indices())
          if (!cell->at_boundary(f) && cell->neighbor_is_coarser(f) && !cell->neighbor(f)->is_artificial() &&
              cell->neighbor(f)->active_fe_index() > 0)
            {
              auto &by = model_of(cell->neighbor(f)) != nullptr ? by_fe : by_pd;
              dofs.resize(cell->get_fe().n_dofs_per_face(f));
              cell->face(f)->get_dof_indices(dofs, cell->active_fe_index());
              by.insert(dofs.begin(), dofs.end());
            }
    for (const auto &line : all.get_lines())
      if (by_pd.count(line.index) == 0 || by_fe.count(line.index) > 0)
        {
          hanging.add_line(line.index);
          hanging.add_entries(line.index, line.entries);
        }
    hanging.close();
  }

  void
  ContinuumField::watch_mesh(const Triangulation<dim> &triangulation)
  {
    if (watched != &triangulation)
      {
        mesh_connections = on_mesh_change(triangulation, [this]() { known_cells.clear(); });
        watched          = &triangulation;
        known_cells.clear();
      }
    known_cells.resize(triangulation.n_active_cells());
  }

  const ContinuumField::CellTerms *
  ContinuumField::known_terms(const CellIterator &cell, const ContinuumModel &model) const
  {
    const KnownCell &known = known_cells[cell->active_cell_index()];
    return known.model == &model && known.fe_index == cell->active_fe_index() ? known.terms : nullptr;
  }

  bool
  ContinuumField::shapes_fit(const DoFHandler<dim>                                              &dof_handler,
                             const std::function<const ContinuumModel *(const CellIterator &)> &model_of) const
  {
    std::set<std::vector<double>> unknown;
    std::size_t                   bytes = kept_bytes;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        if (const ContinuumModel *model = model_of(cell); model != nullptr && known_terms(cell, *model) == nullptr)
          {
            std::vector<double> key = shape_key(cell, *model);
            if (cell_terms.find(key) == cell_terms.end() && unknown.insert(std::move(key)).second)
              {
                const std::size_t n = cell->get_fe().n_dofs_per_cell();
                bytes += sizeof(double) * (n * n + n);
                if (bytes > max_kept_bytes)
                  return false;
              }
          }
    return true;
  }

  void
  ContinuumField::make_matrix()
  {
    const IndexSet &owned    = dofs_of_cells->locally_owned_dofs();
    IndexSet        relevant = partitioner->ghost_indices();
    relevant.add_indices(owned);
    TrilinosWrappers::SparsityPattern pattern(owned, owned, relevant, comm);
    DoFTools::make_sparsity_pattern(*dofs_of_cells, pattern, hanging, false, Utilities::MPI::this_mpi_process(comm));
    pattern.compress();
    K.reinit(pattern);
  }

  void
  ContinuumField::collect_cells(const DoFHandler<dim>                                              &dof_handler,
                                const std::function<const ContinuumModel *(const CellIterator &)> &model_of,
                                const std::function<double(const CellIterator &)>                  &weight_of)
  {
    // Gauss p+1 on FE_Q(p) cells; DG0 (peridynamic) cells are skipped.
    const auto          &fe_collection = dof_handler.get_fe_collection();
    hp::QCollection<dim> quadrature;
    for (unsigned int k = 0; k < fe_collection.size(); ++k)
      quadrature.push_back(QGauss<dim>(std::max(1u, fe_collection[k].degree + 1)));
    hp::FEValues<dim> hp_values(fe_collection, quadrature, update_values | update_gradients | update_JxW_values);
    CellTerms                            computed;
    FullMatrix<double>                   weighted;
    std::vector<types::global_dof_index> dofs;
    element_step = std::numeric_limits<double>::max();
    n_fe_cells   = 0;
    cells.clear();
    cell_dofs.clear();
    expansions.clear();
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const ContinuumModel *model = model_of(cell);
          if (model == nullptr)
            continue;
          ++n_fe_cells;
          // Cells of one shape, element and model share their terms: a box or
          // a locally refined box has a handful of shapes, and a conversion
          // (doc/adaptivity.md) finds them known. A mesh of distinct cells
          // keeps the first max_kept_bytes of them.
          const CellTerms *terms = known_terms(cell, *model);
          if (terms == nullptr)
            terms = terms_by_shape(cell, *model, hp_values, computed);
          known_cells[cell->active_cell_index()] = {terms != &computed ? terms : nullptr, model,
                                                    cell->active_fe_index()};
          element_step = std::min(element_step, terms->step);
          dofs.resize(cell->get_fe().n_dofs_per_cell());
          cell->get_dof_indices(dofs);
          hanging.distribute_local_to_global(terms->mass, dofs, mass);
          if (by_cell)
            add_cell(terms, weight_of(cell), dofs);
          else
            {
              weighted = terms->matrix;
              weighted *= weight_of(cell);
              hanging.distribute_local_to_global(weighted, dofs, K);
            }
        }
  }

  const ContinuumField::CellTerms *
  ContinuumField::terms_by_shape(const CellIterator &cell, const ContinuumModel &model, hp::FEValues<dim> &hp_values,
                                 CellTerms &computed)
  {
    std::vector<double> key   = shape_key(cell, model);
    const auto          known = cell_terms.find(key);
    if (known != cell_terms.end())
      return &known->second;
    hp_values.reinit(cell);
    const FEValues<dim> &fe_values = hp_values.get_present_fe_values();
    model.cell_matrix(fe_values, computed.matrix);
    model.cell_lumped_mass(fe_values, computed.mass);
    computed.step           = LinearElasticity::stable_time_step(computed.matrix, computed.mass);
    const std::size_t bytes = sizeof(double) * (computed.matrix.n_elements() + computed.mass.size());
    if (kept_bytes + bytes > max_kept_bytes)
      return &computed;
    kept_bytes += bytes;
    return &cell_terms.emplace(std::move(key), computed).first->second;
  }

  void
  ContinuumField::add_cell(const CellTerms *terms, const double weight,
                           const std::vector<types::global_dof_index> &dofs)
  {
    FECell c{terms, weight, static_cast<unsigned int>(cell_dofs.size()), static_cast<unsigned int>(expansions.size()),
             static_cast<unsigned int>(expansions.size())};
    for (unsigned int i = 0; i < dofs.size(); ++i)
      {
        cell_dofs.push_back(partitioner->global_to_local(dofs[i]));
        if (hanging.is_constrained(dofs[i]))
          for (const auto &[master, coefficient] : *hanging.get_constraint_entries(dofs[i]))
            expansions.push_back({i, partitioner->global_to_local(master), coefficient});
      }
    c.expansions_end = expansions.size();
    cells.push_back(c);
  }

  void
  ContinuumField::apply_stiffness(const VectorType &src, VectorType &dst) const
  {
    if (!by_cell)
      {
        K.vmult(dst, src);
        return;
      }
    // dst = C^T (sum of w_c K_c) C src: each cell's weighted matrix on its
    // DoF values, a hanging DoF's value from its masters and its force added
    // to them; the sums over cells of other ranks come with compress().
    src.update_ghost_values();
    dst = 0;
    std::vector<double> &u = cell_u, &f = cell_f;
    for (const FECell &c : cells)
      {
        const FullMatrix<double> &A = c.terms->matrix;
        const unsigned int        n = A.m();
        const unsigned int       *d = &cell_dofs[c.dofs];
        u.resize(n);
        f.resize(n);
        for (unsigned int i = 0; i < n; ++i)
          u[i] = src.local_element(d[i]);
        for (unsigned int e = c.expansions_begin; e < c.expansions_end; ++e)
          u[expansions[e].slot] = 0;
        for (unsigned int e = c.expansions_begin; e < c.expansions_end; ++e)
          u[expansions[e].slot] += expansions[e].coefficient * src.local_element(expansions[e].master);
        switch (n) // the trip counts of FE_Q(1) and FE_Q(2) known to the compiler
          {
            case 24:
              weighted_product<24>(&A(0, 0), u.data(), c.weight, f.data(), n);
              break;
            case 81:
              weighted_product<81>(&A(0, 0), u.data(), c.weight, f.data(), n);
              break;
            default:
              weighted_product<0>(&A(0, 0), u.data(), c.weight, f.data(), n);
          }
        for (unsigned int e = c.expansions_begin; e < c.expansions_end; ++e)
          dst.local_element(expansions[e].master) += expansions[e].coefficient * f[expansions[e].slot];
        for (unsigned int e = c.expansions_begin; e < c.expansions_end; ++e)
          f[expansions[e].slot] = 0;
        for (unsigned int i = 0; i < n; ++i)
          dst.local_element(d[i]) += f[i];
      }
    dst.compress(VectorOperation::add);
  }

  const TrilinosWrappers::SparseMatrix &
  ContinuumField::stiffness()
  {
    if (!by_cell || matrix_from_cells)
      return K;
    matrix_from_cells = true;
    // Assembled from the cells' terms on first use (implicit solvers).
    make_matrix();
    FullMatrix<double>                   weighted;
    std::vector<types::global_dof_index> dofs;
    for (const FECell &c : cells)
      {
        const unsigned int n = c.terms->matrix.m();
        dofs.resize(n);
        for (unsigned int i = 0; i < n; ++i)
          dofs[i] = partitioner->local_to_global(cell_dofs[c.dofs + i]);
        weighted = c.terms->matrix;
        weighted *= c.weight;
        hanging.distribute_local_to_global(weighted, dofs, K);
      }
    K.compress(VectorOperation::add);
    return K;
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
    apply_stiffness(U, KU);
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
