#pragma once
// Cells to peridynamic points, and the nonlocal ghost layer.
//
// Every locally owned active cell of a peridynamic block is one point: its
// centroid, its measure as volume, its block. Points are numbered locally as
// owned points first (in the triangulation's cell order, i.e. along p4est's
// space-filling curve), then the nonlocal ghosts in ascending global index:
// the numbering of Utilities::MPI::Partitioner, so that every per-point field
// is a LinearAlgebra::distributed::Vector and the bond arrays index it
// directly. A scalar field uses scalar_partitioner, a vector field (dim
// entries per point, interleaved) vector_partitioner; both describe the same
// ghost set.

#include <perideal/base/input.h>
#include <perideal/geometry/periodicity.h>

#include <deal.II/base/partitioner.h>
#include <deal.II/base/point.h>
#include <deal.II/dofs/dof_handler.h>

#include <boost/signals2/connection.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace perideal
{
  using CellIterator = dealii::DoFHandler<dim>::active_cell_iterator;

  /// @p cell as a cell of @p dofs (another numbering of its triangulation).
  inline CellIterator
  on(const dealii::DoFHandler<dim> &dofs, const CellIterator &cell)
  {
    return CellIterator(&dofs.get_triangulation(), cell->level(), cell->index(), &dofs);
  }
  using PointKey     = std::array<unsigned int, 4>;

  /// Calls @p forget whenever the cells of @p triangulation change (created,
  /// refined, coarsened, partitioned again or loaded): what is kept per
  /// active cell is stale then. The connections end with the returned
  /// objects.
  std::vector<boost::signals2::scoped_connection>
  on_mesh_change(const dealii::Triangulation<dim> &triangulation, const std::function<void()> &forget);

  /// Each active cell's centroid and volume (cell_centroid(),
  /// cell_volume()), computed when first asked for and kept until clear():
  /// the rebuilds of a run ask for the same cells' again (twice in a
  /// coupled rebuild, and in every conversion that does not refine).
  class CellGeometry
  {
  public:
    /// Forgets every cell's: call it whenever the mesh changes.
    void
    clear()
    {
      data.clear();
    }
    /// @p cell's centroid and volume.
    std::pair<dealii::Point<dim>, double>
    operator()(const CellIterator &cell);

  private:
    std::vector<double> data; // per active cell: the centroid's dim coordinates, the volume (NaN: not yet)
  };

  class PointCloud
  {
  public:
    /// A point that no cell makes: the nodes at which force blending
    /// evaluates the PD force (doc/coupling.md). Appended after the cells'
    /// points of its rank; its key must start with extra_key and be unique
    /// and rank-independent.
    struct ExtraPoint
    {
      dealii::Point<dim> x;
      double             volume;
      unsigned short     block;
      PointKey           key;
      CellIterator       cell; // a locally owned cell holding it
    };

    /**
     * Points from the locally owned cells for which @p block_of returns a
     * block number (-1: not a peridynamic cell); then every point owned
     * elsewhere that lies within @p max_horizon of this rank's bounding box
     * is received as a ghost candidate. Collective.
     *
     * With @p levels_of, a cell for which it returns r > 0 gives 8^r points
     * instead of one: the centroids of the cells r refinements below it (Q1
     * map of the lattice (i + 1/2)/2^r of the unit cell), each with 1/8^r of
     * the cell's measure and the CellId of that descendant as key. These are
     * the virtual points of the FE-PD coupling (doc/coupling.md).
     *
     * With @p cell_geometry, every point (ghosts too) also carries the 8
     * vertices of its cell in cell_vertices, and the ghost reach grows by
     * the largest cell radius (max_cell_radius): what partial volumes need.
     *
     * Set periodicity first: a point near a periodic face is then also a
     * ghost candidate of the ranks near the opposite face.
     *
     * @p extra points follow the cells' points of this rank (with the cell
     * geometry, their cell's vertices).
     *
     * @p geometry, if given, supplies the cells' centroids and volumes.
     */
    void
    build(const dealii::DoFHandler<dim>                         &dof_handler,
          const std::function<int(const CellIterator &)>          &block_of,
          const double                                            max_horizon,
          const MPI_Comm                                          comm,
          const std::function<unsigned int(const CellIterator &)> &levels_of     = {},
          const bool                                               cell_geometry = false,
          const std::vector<ExtraPoint>                           &extra         = {},
          CellGeometry                                            *geometry      = nullptr);

    /**
     * Keep only the ghost candidates marked in @p used (indexed by local
     * point), renumber them after the owned points in ascending global index
     * and build the partitioners. Returns the new local index of every old
     * one (unsigned(-1) for dropped ghosts).
     */
    std::vector<unsigned int>
    finalize_ghosts(const std::vector<bool> &used, const MPI_Comm comm);

    unsigned int
    n_owned() const
    {
      return n_owned_points;
    }
    unsigned int
    n_local() const
    {
      return volume.size();
    }
    dealii::types::global_dof_index
    n_global() const
    {
      return n_global_points;
    }

    dealii::Point<dim>
    position(const unsigned int i) const
    {
      return {X[3 * i], X[3 * i + 1], X[3 * i + 2]};
    }

    /// The first word of an ExtraPoint's key (no CellId has it).
    static constexpr unsigned int extra_key = 0xFFFFFFFFu;
    /// Whether local point @p i is an ExtraPoint: it has bonds to the
    /// points around it, but no point has a bond to it.
    bool
    is_extra(const unsigned int i) const
    {
      return key[i][0] == extra_key;
    }

    /// A 64-bit hash of the point's key: the same on any number of ranks.
    std::uint64_t
    hash(const unsigned int i) const;

    std::vector<double>                          X;      // reference position, dim per point
    std::vector<double>                          volume; // cell measure
    std::vector<unsigned short>                  block;  // block number
    std::vector<PointKey>                        key;    // CellId: rank-independent identity and order
    std::vector<dealii::types::global_dof_index> gid;    // global point index
    std::vector<CellIterator>                    cell;   // owned points only: the cell holding the point
    std::vector<double> cell_vertices;   // with cell geometry only (set-up): 8 vertices x dim per point
    double              max_cell_radius = 0; // with cell geometry: the largest centroid-to-vertex distance
    Periodicity         periodicity;         // bond vectors are wrap(X_j - X_i) where periodic

    /// The reference bond vector i -> j (the minimum image where periodic).
    dealii::Tensor<1, dim>
    bond_vector(const unsigned int i, const unsigned int j) const
    {
      double e[3] = {X[3 * j] - X[3 * i], X[3 * j + 1] - X[3 * i + 1], X[3 * j + 2] - X[3 * i + 2]};
      if (periodicity.any())
        periodicity.wrap(e[0], e[1], e[2]);
      return dealii::Tensor<1, dim>({e[0], e[1], e[2]});
    }

    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> scalar_partitioner;
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> vector_partitioner;

  private:
    unsigned int                    n_owned_points  = 0;
    dealii::types::global_dof_index n_global_points = 0;
    dealii::types::global_dof_index first_gid       = 0;
  };
} // namespace perideal
