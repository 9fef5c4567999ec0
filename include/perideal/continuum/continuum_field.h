#pragma once
// The finite element part of a run with continuum blocks (doc/coupling.md):
// the FE_Q(p)^dim cells of the simulation's hp DoFHandler with their
// displacement, velocity and force vectors, the row-sum lumped mass, the
// stiffness matrix (each cell's weighted by its energy weight 1 - alpha of
// the blending band), the hanging-node constraints of locally refined FE
// regions, and Pi, the interpolation of the FE field at the virtual points
// through which peridynamic families reach into FE cells. The explicit
// integrator touches only the flat list of owned free DoFs.

#include <perideal/base/input.h>
#include <perideal/continuum/linear_elasticity.h>
#include <perideal/continuum/point_interpolation.h>
#include <perideal/discretization/point_cloud.h>

#include <deal.II/base/partitioner.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/hp/fe_values.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <functional>
#include <map>
#include <memory>
#include <vector>

namespace perideal
{
  /// An owned DoF of a cell: index within the locally owned DoFs, vector
  /// component, support point (Q1 map) and a locally owned cell holding it.
  struct DoFNode
  {
    unsigned int       local;
    unsigned int       component;
    dealii::Point<dim> x;
    CellIterator       cell;
  };

  /// The locally owned DoFs of the cells @p selected accepts (all if
  /// empty), each once, in the order the cells first reach them: the
  /// locally owned cells, then the ghost cells.
  std::vector<DoFNode>
  owned_nodes(const dealii::DoFHandler<dim>                      &dof_handler,
              const std::function<bool(const CellIterator &)>  &selected = {});

  class ContinuumField
  {
  public:
    using VectorType = dealii::LinearAlgebra::distributed::Vector<double>;

    /// An owned DoF of an FE cell (for conditions and computes).
    using Node = DoFNode;

    ContinuumField() = default;
    // Not copied or moved: the mesh's signals call back into this object.
    ContinuumField(const ContinuumField &) = delete;
    ContinuumField &
    operator=(const ContinuumField &) = delete;

    /// The cells for which @p model_of returns a model are the FE cells (an
    /// FE_Q(p)^dim element active on them); @p weight_of gives a cell's
    /// energy weight in [0, 1]. Assembles mass and stiffness. Collective.
    void
    setup(const dealii::DoFHandler<dim>                                         &dof_handler,
          const std::function<const ContinuumModel *(const CellIterator &)> &model_of,
          const std::function<double(const CellIterator &)>                    &weight_of,
          const MPI_Comm                                                        comm);

    /// The virtual points (inside locally owned FE cells) whose displacement
    /// interpolate() gives and whose forces compute_force() takes.
    void
    set_virtual_points(const dealii::DoFHandler<dim>                                   &dof_handler,
                       const std::vector<std::pair<CellIterator, dealii::Point<dim>>> &points);

    /// u (dim per virtual point) = Pi U; U's ghost values must be current.
    void
    interpolate(std::vector<double> &u) const
    {
      Pi.interpolate(U, u);
    }

    /// F = Pi^T f_virtual - K U + load on the owned DoFs; @p f_virtual holds
    /// V f (force, not density) per virtual point and component. Without
    /// @p transpose, F = -K U + load (@p f_virtual is not read).
    void
    compute_force(const std::vector<double> &f_virtual, const bool transpose = true);

    /// load += the nodal forces of a traction, one component, force per area,
    /// @p value at each face's centre, on @p faces (boundary faces of owned
    /// FE cells). Compress load with VectorOperation::add after the last.
    void
    add_face_load(const std::vector<std::pair<CellIterator, unsigned int>> &faces,
                  const unsigned int                                       component,
                  const std::function<double(const dealii::Point<dim> &)> &value);

    /// The largest stable explicit step of the FE cells: the smallest element
    /// bound 2 / sqrt(lambda_max(M_e^-1 K_e)) of the unweighted stiffness.
    /// Collective.
    double
    stable_time_step() const;

    /// 1/2 U.K U and 1/2 V.M V over all ranks (after compute_force()).
    double
    strain_energy() const;
    double
    kinetic_energy() const;
    /// 1/2 V.M V of this rank's DoFs (no communication).
    double
    local_kinetic_energy() const;

    /// dst = K src on the owned DoFs: the energy-weighted stiffness,
    /// condensed by the hanging-node constraints (its rows at hanging DoFs
    /// are not to be read). @p src's ghost values are updated here.
    void
    apply_stiffness(const VectorType &src, VectorType &dst) const;

    /// The same stiffness as a matrix (the implicit solvers' tangent).
    /// Explicit runs do without it: when the cells have few shapes (a box, a
    /// refined box) it is assembled only at the first call. Collective then.
    const dealii::TrilinosWrappers::SparseMatrix &
    stiffness();
    const PointInterpolation &
    interpolation() const
    {
      return Pi;
    }
    /// Owned and locally relevant DoFs: the layout of U, V, F, mass and load.
    const std::shared_ptr<const dealii::Utilities::MPI::Partitioner> &
    vector_partitioner() const
    {
      return partitioner;
    }

    bool
    empty() const
    {
      return n_fe_cells == 0;
    }

    /// Whether apply_stiffness() goes cell by cell (set by setup()).
    bool
    applied_by_cell() const
    {
      return by_cell;
    }

    /// The bytes of cell terms kept by shape (continuum_field.cc): when a
    /// set-up's shapes need more on some rank, the stiffness is assembled
    /// into a matrix instead. Set before setup().
    std::size_t max_kept_bytes = 8 << 20;

    std::vector<Node>         nodes; // owned DoFs of FE cells
    std::vector<unsigned int> free;  // local indices of owned FE DoFs not constrained by hanging nodes
    VectorType                U, V, F, mass, load; // U ghosted; load: nodal body force, may stay empty
    dealii::AffineConstraints<double> hanging;
    dealii::types::global_dof_index   n_global_dofs = 0; // of FE cells, all ranks

  private:
    /// A cell's unweighted matrix, lumped mass and stable step.
    struct CellTerms
    {
      dealii::FullMatrix<double> matrix;
      dealii::Vector<double>     mass;
      double                     step = 0;
    };

    /// Whether the shapes of this rank's FE cells not yet known fit in
    /// max_kept_bytes (then the stiffness is applied cell by cell).
    bool
    shapes_fit(const dealii::DoFHandler<dim>                                         &dof_handler,
               const std::function<const ContinuumModel *(const CellIterator &)> &model_of) const;

    /// The mass, the stable step and, cell by cell (by_cell) or assembled
    /// into K, the stiffness of the FE cells (setup()).
    void
    collect_cells(const dealii::DoFHandler<dim>                                         &dof_handler,
                  const std::function<const ContinuumModel *(const CellIterator &)> &model_of,
                  const std::function<double(const CellIterator &)>                    &weight_of);

    /// The terms of @p cell's shape: kept ones, else computed (into
    /// cell_terms, or into @p computed once max_kept_bytes are kept).
    const CellTerms *
    terms_by_shape(const CellIterator &cell, const ContinuumModel &model, dealii::hp::FEValues<dim> &hp_values,
                   CellTerms &computed);

    /// K's sparsity pattern, entries zero. Collective.
    void
    make_matrix();

    /// hanging: the constraints of the hanging nodes between FE cells
    /// (those of @p model_of) on the locally @p relevant DoFs.
    void
    make_hanging_constraints(const dealii::DoFHandler<dim>                                         &dof_handler,
                             const std::function<const ContinuumModel *(const CellIterator &)> &model_of,
                             const dealii::IndexSet                                                &relevant);

    /// One FE cell for apply_stiffness().
    void
    add_cell(const CellTerms *terms, const double weight, const std::vector<dealii::types::global_dof_index> &dofs);

    /// An FE cell applied by apply_stiffness(): its shape's terms, its energy
    /// weight, its DoFs (local indices from cell_dofs[dofs]) and the
    /// hanging DoFs among them (expansions[expansions_begin, end)).
    struct FECell
    {
      const CellTerms *terms;
      double           weight;
      unsigned int     dofs, expansions_begin, expansions_end;
    };
    /// A hanging DoF of a cell (its place in the cell) and one of its masters.
    struct Expansion
    {
      unsigned int slot, master;
      double       coefficient;
    };
    bool                                  by_cell           = false;
    bool                                  matrix_from_cells = false;
    const dealii::DoFHandler<dim>        *dofs_of_cells     = nullptr;
    std::vector<FECell>                   cells;
    std::vector<unsigned int>             cell_dofs;
    std::vector<Expansion>                expansions;
    mutable std::vector<double>           cell_u, cell_f; // apply_stiffness()'s scratch
    /// By shape (continuum_field.cc), kept across set-ups: a conversion's
    /// new set-up finds the shapes it knows. At most max_kept_bytes of
    /// matrices (4.6 KiB each for FE_Q(1) in 3D, 51 KiB for FE_Q(2)).
    std::map<std::vector<double>, CellTerms> cell_terms;
    std::size_t                              kept_bytes = 0;
    /// Per active cell: the kept terms it had at the last set-up, its model
    /// and element then (a conversion's set-up finds them without making
    /// its shape's key again). Forgotten whenever the mesh changes (the
    /// triangulation's signals), as the cells' numbers do.
    struct KnownCell
    {
      const CellTerms      *terms    = nullptr;
      const ContinuumModel *model    = nullptr;
      unsigned int          fe_index = 0;
    };
    std::vector<KnownCell>                          known_cells;
    std::vector<boost::signals2::scoped_connection> mesh_connections;
    const dealii::Triangulation<dim>               *watched = nullptr;
    /// The kept terms @p cell had at the last set-up with the same model
    /// and element, or nullptr.
    const CellTerms *
    known_terms(const CellIterator &cell, const ContinuumModel &model) const;
    /// Forgets known_cells when @p triangulation changes (connects once).
    void
    watch_mesh(const dealii::Triangulation<dim> &triangulation);

    MPI_Comm                                                 comm = MPI_COMM_SELF;
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> partitioner;
    dealii::TrilinosWrappers::SparseMatrix                   K;
    VectorType                                               KU;
    double                                                   element_step = 0;
    PointInterpolation                                       Pi;
    std::unique_ptr<dealii::hp::FEFaceValues<dim>>           face_values; // made at the first traction
    std::size_t                                              n_fe_cells = 0;
  };
} // namespace perideal
