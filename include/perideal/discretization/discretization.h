#pragma once
// The discretization: the mesh (a built-in scene or a Gmsh file, refined in
// regions), the hp DoFHandler (FE_DGQ(0)^dim on peridynamic cells, FE_Q(p)^dim
// on continuum cells), the point cloud (one point per PD cell, virtual points
// in FE cells within reach of them) and the bonds (families within the
// horizon, bond filters, partial volumes), repartitioned by bonds on several
// ranks. The size of the scene is checked against the memory before each
// allocation (size_check.cc).

#include <perideal/base/memory.h>
#include <perideal/discretization/point_cloud.h>
#include <perideal/damage/initial_damage.h>
#include <perideal/geometry/region.h>
#include <perideal/geometry/scene.h>
#include <perideal/model/block.h>
#include <perideal/neighborhood/bond_filter.h>
#include <perideal/neighborhood/bonds.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/cell_id.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/hp/fe_collection.h>

#include <boost/signals2/connection.hpp>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <cmath>
#include <vector>

namespace perideal
{
  struct Deck;
  struct ContactParameters;

  /// The coupling band before a change of the mesh (Adaptivity): each
  /// owned FE cell's FE weight, virtual point levels and its virtual
  /// points' blending weights; and where peridynamic points may have
  /// appeared since: within @p radius of one of @p centres (every rank's;
  /// none: no point appeared, a rebalance). A cell farther from all of them
  /// than the band can reach keeps its entry (build_coupled_cloud()).
  struct PreviousCoupling
  {
    struct Cell
    {
      dealii::CellId id;
      double         fe_weight;
      unsigned char  levels;      // Discretization::cell_virtual
      unsigned int   first_alpha; // its virtual points' weights: alpha[first_alpha, + 8^(levels - 1))
      bool
      operator<(const Cell &other) const
      {
        return id < other.id;
      }
    };
    std::vector<Cell>               cells; // sorted by id
    std::vector<double>             alpha;
    std::vector<dealii::Point<dim>> centres;
    double                          radius = 0;
  };

  class Discretization
  {
  public:
    Discretization(Deck &deck, const MPI_Comm comm, dealii::ConditionalOStream &pcout, dealii::TimerOutput &timer,
                   const bool dry_run_mode);

    /// Mesh, refinement, points and bonds, rebalanced by bonds on several
    /// ranks; then every point has a neighbor. Collective.
    void
    setup();

    /// Makes the points and bonds again after cells were marked in
    /// converted (Adaptivity), on the same mesh and partition. Collective.
    void
    rebuild_points_and_bonds();

    /// The ranks' work out of balance: the largest rank's bonds (plus a few
    /// per point and one per cell) over the mean, minus 1. Collective.
    double
    work_imbalance() const;
    /// Sets each owned cell's user index to its weight (bonds + 4 per point,
    /// its virtual points' for an FE cell, 1 without a point) and lets p4est
    /// partition the mesh by them; the points and bonds must be made again.
    /// Collective.
    void
    repartition_by_work();
    /// Each owned cell's user index = its weight for repartition_by_work().
    void
    set_cell_weights();
    /// p4est partitions the mesh by the owned cells' user indices. Collective.
    void
    repartition_by_cell_weights();

    /// Whether @p x (in @p cell) lies in the region named @p region ("All": everywhere).
    bool
    in_region(const std::string &region, const dealii::Point<dim> &x, const CellIterator &cell) const
    {
      return region == "All" || regions.at(region)->contains(x, cell);
    }
    /// The owned points in @p region, virtual points left out, in
    /// increasing order. After a rebuild that knows previous_point, a point
    /// that is there unchanged takes its answer from @p before (what this
    /// call gave for the region before the rebuild, in the indices then)
    /// instead of asking the region again: in or out depends only on the
    /// point's place and cell. With Adaptivity/Check kept families every
    /// point is asked as well, and a differing answer stops the run
    /// (collective then).
    std::vector<unsigned int>
    points_in_region(const std::string &region, const std::vector<unsigned int> &before) const;
    /// Collective: stops if a region's expression was not finite at a point
    /// it was asked about (NaN would silently put the point inside).
    void
    check_region_expressions() const;
    /// The block that claims @p cell: the converted cells' block for a
    /// converted cell, else the first whose region or material ids hold
    /// it, -1 if none.
    int
    block_of_cell(const CellIterator &cell) const;
    /// An FE cell: one of a continuum block that has not converted. A
    /// converted cell keeps the active FE index (FE_Q(p)) it had, so that a
    /// conversion does not number the DoFs again: the index alone does not
    /// say whether a cell is FE.
    bool
    is_fe_cell(const CellIterator &cell) const
    {
      return cell->active_fe_index() > 0 && (converted.empty() || !converted[cell->active_cell_index()]);
    }
    /// An FE cell of the points and bonds as last built: between marking
    /// cells converted and the rebuild, the cells that convert still are.
    /// Only on the mesh they were built on (after a refinement or a move
    /// every cell of a continuum block counts).
    bool
    was_fe_cell(const CellIterator &cell) const
    {
      return cell->active_fe_index() > 0 &&
             (converted_when_built.empty() || !converted_when_built[cell->active_cell_index()]);
    }
    /// A point of a continuum block: it follows the FE field.
    bool
    is_virtual(const unsigned int i) const
    {
      return has_continuum && blocks[cloud.block[i]].continuum;
    }
    /// The smallest point spacing, (cell volume)^(1/3), over the points with mass. Collective.
    double
    point_spacing() const;
    /// Coupling/Blending width: the band's width in horizons.
    double
    blending() const
    {
      return blending_width;
    }
    /// How far from the nearest PD point (of horizon @p horizon) an FE cell
    /// holds virtual points: the blending band and a horizon beyond it (two
    /// with force blending, whose node points need complete families).
    double
    virtual_point_reach(const double horizon) const
    {
      return blending_width * horizon + (force_blending ? 2 : 1) * horizon;
    }
    /// The levels of virtual points in an FE cell of volume @p cell_volume
    /// near PD points of volume @p point_volume: Virtual point levels, or
    /// (auto) those that put them at the PD spacing.
    int
    virtual_levels(const double cell_volume, const double point_volume) const
    {
      return virtual_point_levels >= 0 ?
               virtual_point_levels :
               std::max(0, int(std::lround(std::log2(std::cbrt(cell_volume / point_volume)))));
    }
    /// The longest bond find_families() can make: the largest horizon with
    /// its tolerance plus the search's extra reach (the largest cell
    /// radius), a millionth more.
    double
    longest_bond(const std::vector<double> &horizon) const;
    /// The coupling band as it is now (PreviousCoupling; no centres yet),
    /// to be set as previous_coupling around the next rebuild. Energy
    /// blending only (force blending's node points are made again): empty
    /// otherwise.
    PreviousCoupling
    record_coupling() const;
    /// The horizon key of the block with the largest horizon, for messages.
    std::string
    horizon_key() const;

    const Scene                                          &scene;
    const std::map<std::string, std::unique_ptr<Region>> &regions;
    const std::vector<BondFilter>                        &bond_filters;
    const std::vector<InitialDamage>                     &initial_damage;
    std::vector<Block>                                   &blocks;
    const ContactParameters &contact; // which blocks may hold particles without bonds
    const bool                                            has_continuum;
    const bool force_blending; // Coupling/Scheme = force blending
    // Adaptivity/Refine converted cells: the triangulation repartitions
    // only when asked (conversions refine cells in place).
    const bool conversions_refine;

    dealii::parallel::distributed::Triangulation<dim> triangulation;
    // FE_DGQ(0)^dim on PD cells (active FE index 0), FE_Q(p)^dim on the cells
    // of continuum blocks (index p), converted cells too (is_fe_cell()):
    // the DoFs are numbered when the mesh changes, not when cells convert.
    dealii::hp::FECollection<dim> fe;
    dealii::DoFHandler<dim>       dof_handler;
    PointCloud                    cloud;
    Bonds                         bonds;
    std::vector<std::size_t>      filtered_bonds;       // per filter: directed bonds it cut in the searched families (all ranks; the set-up's: all)
    std::vector<std::uint8_t>     initially_broken;     // per bond: 1 if it starts broken; empty without initial damage
    std::vector<std::size_t>      initially_broken_bonds; // per initial damage entry: directed bonds it broke (all ranks)
    double                        unbalanced_bonds = 0; // % above the mean before rebalancing, 0: not needed
    /// What setup() found suspicious but legal (points without a neighbor),
    /// for the run's warnings.
    std::vector<std::string>      setup_warnings;
    // Continuum runs: the PD energy weight per owned point, 1 - alpha per
    // active FE cell, and per active cell 1 + its virtual point levels (0: none).
    std::vector<double>        point_alpha;
    std::vector<double>        cell_fe_weight;
    std::vector<unsigned char> cell_virtual;
    // Force blending (Coupling/Scheme): per owned free FE node within the
    // band, a point at the node where the PD force is evaluated (owned
    // point index), its dim global DoFs and its weight alpha.
    std::vector<unsigned int>                     node_points;
    std::vector<dealii::types::global_dof_index> node_point_dofs;
    std::vector<double>                           node_point_alpha;
    // Adaptivity: per active cell (owned and ghost), 1 if it has turned
    // into a cell of block converted_block; empty before any conversion.
    std::vector<std::uint8_t> converted;
    unsigned int              converted_block = 0;
    // converted as the points and bonds were last built with it; empty
    // from a change of the mesh to the next build.
    std::vector<std::uint8_t> converted_when_built;
    // Set by Adaptivity around a rebuild: the families that points far
    // from the converted cells keep (find_families()); nullptr: search all.
    const PreviousFamilies *previous_families = nullptr;
    // Set by Adaptivity around a rebuild: the coupling band the FE cells far
    // from the converted ones keep (build_coupled_cloud()); nullptr: all
    // cells find their nearest PD point again.
    const PreviousCoupling *previous_coupling = nullptr;
    // After a rebuild with previous_families, per owned point: its index
    // before the rebuild if it was this rank's with the same key, block,
    // blending weight and place, else numbers::invalid_unsigned_int (what
    // depends only on these is carried over, not computed again). Empty:
    // nothing known (the set-up, a restart).
    std::vector<unsigned int> previous_point;
    // Adaptivity/Check kept families: every rebuild with previous_families
    // searches all families again (and finds the coupling band of every FE
    // cell again) and stops if a kept one differs.
    bool check_kept_families = false;

  private:
    /// Per owned point, sorted by key: its key and its family's keys in order.
    std::vector<std::pair<PointKey, std::vector<PointKey>>>
    families_by_key() const;
    /// Per owned point, and per owned FE cell (by its CellId's key), sorted:
    /// the point's blending weight; the cell's -1, FE weight and levels.
    std::vector<std::pair<PointKey, std::vector<double>>>
    coupling_by_key() const;
    /// Builds the points and bonds again without previous_families and
    /// previous_coupling and stops with an Error if a family, an FE cell's
    /// weight or levels or a point's blending weight differs from the kept
    /// ones. Collective.
    void
    compare_with_searched_families();
    /// Per active cell: the entry of previous_coupling an owned FE cell
    /// keeps, or unsigned(-1) if its nearest PD point must be found again
    /// (@p largest_pd_cell: the largest PD cell's diameter, every rank's).
    std::vector<unsigned int>
    kept_coupling(const double max_horizon, const double largest_pd_cell) const;
    /// @p previous with the changed points (every rank's) and the radius
    /// within which their families must be searched again. Collective.
    /// Also fills previous_point.
    PreviousFamilies
    with_changed_points(const PreviousFamilies &previous, const std::vector<double> &horizon);

    /// Size checks (size_check.cc): the built-in scene's cells, points and
    /// bonds before the mesh is made, and the mesh's (with the cells flagged
    /// for refinement) once it exists, against the memory available; an
    /// Error naming the key if too large. Collective.
    void
    check_scene_size(const AvailableMemory &available) const;
    void
    check_mesh_size(const AvailableMemory &available, const std::string &what, const std::string &cells_key,
                    const double descendants = 0) const; // > 0: every cell becomes this many
    /// Collective: stops, naming the block and why, if a block of
    /// Blocks/Names claims no cell (a silent no-op otherwise).
    void
    check_blocks_have_cells() const;
    /// The block whose region or material ids claim @p cell (the first),
    /// converted or not; -1 if none.
    int
    claiming_block(const CellIterator &cell) const;
    /// Each owned cell's element from its claiming block and the DoFs
    /// numbered, unless numbered since the mesh last changed. Collective.
    void
    number_dofs();
    /// Collective: stops if a point's cell has no positive volume, naming
    /// the cell and whether it is below the resolution of a double.
    void
    check_cell_volumes() const;
    /// DoFs, point cloud and families of the current partition.
    void
    build_points_and_bonds();
    /// Removes the bonds that cross a bond filter; counts them per filter.
    void
    apply_bond_filters();
    /// Marks the bonds of the initial damage entries broken
    /// (initially_broken); counts them per entry. Collective.
    void
    apply_initial_damage();
    /// Points without a neighbor (outside contact and rigid blocks): a
    /// warning with how many and the first (each moves freely under its
    /// conditions, as in Peridigm); an Error if every point of the body is
    /// one (a horizon below the spacing everywhere: no bond at all).
    /// Collective.
    void
    check_isolated_points();
    /// The point cloud of a run with continuum blocks: PD points and the
    /// virtual points of the FE cells within reach of them, with alpha (PD
    /// energy weight) per point and 1 - alpha per FE cell from the distance
    /// to the nearest PD point.
    void
    build_coupled_cloud(const std::function<int(const CellIterator &)> &block_of, const double max_horizon);
    /// Removes the bonds between two points of energy weight 0 (virtual
    /// points beyond the band): they carry no energy, and such a point needs
    /// only its bonds to weighted points to receive their reactions.
    void
    drop_unweighted_bonds();
    /// Force blending: the node points of the owned free FE nodes whose
    /// weight alpha is positive: 1 on a node of a PD cell's closure, falling
    /// linearly to 0 over the band with the distance to the nearest PD cell
    /// of @p nearby (its points of other blocks than @p probe, with their
    /// cells' vertices). Sets node_point_dofs and node_point_alpha.
    std::vector<PointCloud::ExtraPoint>
    make_node_points(const PointCloud &nearby, const int probe, const std::function<int(const CellIterator &)> &block_of,
                     const double max_horizon);

    MPI_Comm                   comm;
    dealii::ConditionalOStream &pcout;
    dealii::TimerOutput        &timer;
    double                      blending_width;
    int                         virtual_point_levels;
    bool                        dry_run_mode;
    // The cells' centroids and volumes for build_coupled_cloud(), forgotten
    // whenever the mesh changes (the connections, declared after it, are
    // released first).
    CellGeometry                                        cell_geometry;
    std::vector<boost::signals2::scoped_connection>     geometry_connections;
    // The DoFs are numbered for the mesh as it is: false from a change of
    // the mesh (refinement, repartition, load) to the next numbering.
    bool dofs_numbered = false;
  };
} // namespace perideal
