#pragma once
// Cells that turn into peridynamics during a run (doc/adaptivity.md).
//
// Every Check interval steps the FE cells of the convertible continuum
// blocks are tested by an indicator evaluated on the FE side (there is no PD
// damage before a cell converts); each cell that passes, and every
// convertible cell within the buffer of one, becomes a cell of the named
// peridynamic block: its point takes the FE displacement and velocity at its
// centroid (the FE interpolation of its own cell), its bonds start intact
// with reference lengths from the reference positions. The points, bonds,
// ghosts, coupling band, masses, conditions and stable step are then made
// again for the new set of PD cells on the same mesh and partition, and the
// state of every point, bond and FE node that existed before is carried
// over by its identity (CellId keys, cell-local FE values), so that the
// displacement, velocity, momentum and the damage and history so far are
// continuous.

#include <perideal/adaptivity/adaptivity_parameters.h>
#include <perideal/conditions/boundary_conditions.h>
#include <perideal/model/state.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/point.h>
#include <deal.II/base/timer.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/grid/tria.h>

#include <boost/range/iterator_range.hpp>
#include <deal.II/hp/fe_values.h>

#include <array>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace perideal
{
  class Discretization;
  struct PreviousCoupling;
  class ForceModel;
  class Coupling;
  class Postprocess;

  class Adaptivity
  {
  public:
    /// @p rebuild(t) makes the points, bonds and every part that depends on
    /// them again for the cells marked in the discretization, with the
    /// loads of time t (Simulation).
    Adaptivity(const AdaptivityParameters &parameters, Discretization &discretization, ForceModel &model,
               Coupling &coupling, Postprocess &post, MechanicalState &state, RunRecord &record, const MPI_Comm comm,
               dealii::ConditionalOStream &pcout, dealii::TimerOutput &timer, std::function<void(double)> rebuild);

    /// The integrator that runs now (each Solver stage's calls this):
    /// explicit steps are checked every Check interval steps (0: 10),
    /// implicit ones after every accepted step (or every Check interval);
    /// without inertia (QuasiStatic) no wave moves between checks.
    void
    use_integrator(const bool explicit_steps, const bool with_inertia);
    /// Whether the integrator that runs now has inertia (use_integrator()).
    bool
    has_inertia() const
    {
      return inertia;
    }
    /// Whether step @p step is a check step.
    bool
    due(const unsigned int step) const
    {
      return step % interval == 0;
    }
    /// The check after the accepted step @p step at @p time: converts the
    /// cells the indicator flags (with their buffer), rebuilds, carries the
    /// state over, evaluates the forces of the new model and logs the
    /// conversion. @p dt is the step the buffer's wave distance is for.
    /// Returns true if cells converted (the integrator then takes the new
    /// numbering). Collective.
    bool
    check(const unsigned int step, const double time, const double dt);

    /// A restart: the cells a checkpoint says were converted (per active
    /// cell of this rank, empty or all 0 if none), their points, bonds and
    /// parts made as at the conversions, before the state is read.
    /// Collective.
    void
    restore_converted(const std::vector<std::uint8_t> &converted);
    /// How the conversions so far changed this rank's mesh and partition,
    /// for a checkpoint: the events in order (the same on every rank), a
    /// refinement pass (0) or a rebalance (1); per pass the owned cells it
    /// split, per rebalance each owned cell's weight.
    struct MeshHistory
    {
      std::vector<std::uint8_t>                      events;
      std::vector<std::pair<unsigned int, PointKey>> split;   // (event, CellId)
      std::vector<std::pair<unsigned int, PointKey>> weighed; // (event, CellId)
      std::vector<unsigned int>                      weights; // per weighed cell
    };
    /// Whether conversions may refine cells or move them between ranks
    /// (Refine converted cells, Rebalance threshold): then a checkpoint
    /// holds the mesh history.
    bool
    changes_mesh() const
    {
      return parameters.refine || parameters.rebalance > 0;
    }
    const MeshHistory &
    mesh_history() const
    {
      return history;
    }
    /// A restart: refines and partitions the mesh as the conversions before
    /// the checkpoint did (@p events from mesh_history()), before
    /// restore_converted(). Collective.
    void
    replay(const MeshHistory &events);
    /// Whether cells have converted (in this run, or before its checkpoint:
    /// the record comes with it).
    bool
    any_converted() const
    {
      return record.conversions > 0;
    }

    /// The set-up report's line: the blocks, the indicator, the interval
    /// and the buffer with the run's time step.
    void
    report_setup() const;

    /// The buffer width used with time step @p dt: the parameter, or the
    /// rule horizon + blending band + fastest wave speed x check interval x
    /// dt (no wave term without inertia).
    double
    buffer_width(const double dt) const;

  private:
    /// Where this rank's indicator passes: the centres of its FE cells (or
    /// the positions of its damaged PD points) past the threshold.
    std::vector<dealii::Point<dim>>
    find_triggers() const;
    /// The indicator's value at one owned FE cell of a convertible block
    /// (@p values: a midpoint rule with gradients).
    double
    cell_indicator(const CellIterator &cell, dealii::hp::FEValues<dim> &values) const;
    /// If a convertible cell's centre lies within @p width of a trigger of
    /// any rank, marks every convertible cell (owned and ghost) within
    /// @p width plus the Buffer margin; returns the owned cells it marked.
    /// Collective.
    std::size_t
    mark_cells(const std::vector<dealii::Point<dim>> &triggers, const double width);
    /// Refine converted cells: splits the converted cells coarser than
    /// target_level, pass by pass, and flags their children converted;
    /// returns the passes made. Collective.
    unsigned int
    refine_converted_cells();
    /// One refinement pass of the flagged cells: the converted flags follow
    /// the cells to their children; an Error if p4est's balance would
    /// refine a peridynamic cell (its point's state has no FE field to
    /// come from). Collective.
    void
    execute_refinement();
    /// Kinetic and strain energy of the current state (its ghosts updated,
    /// forces evaluated with energy). Collective.
    std::pair<double, double>
    energies();

    /// The state that survives a conversion, by identity (adaptivity.cc).
    struct Snapshot;
    /// The families of @p old, for the points the rebuild leaves unchanged
    /// far enough from every changed one to keep them.
    PreviousFamilies
    families_to_keep(const Snapshot &old) const;
    /// The state now. @p bonds_with_state_only (a rebalance): each family
    /// lists only its broken or damaged bonds and those with a history, to
    /// move less; the families are then searched again.
    Snapshot
    take_snapshot(const bool bonds_with_state_only = false) const;
    /// The old owned point with key @p key, or unsigned(-1).
    unsigned int
    old_point(const Snapshot &old, const PointKey &key) const;
    /// The points, bonds and parts made again (the families far from the
    /// changes kept from @p old, or those of @p keep; the coupling band
    /// far from them from @p band), then restore(@p old). Collective.
    void
    rebuild_and_restore(const Snapshot &old, const double time, const PreviousCoupling &band,
                        const PreviousFamilies *keep = nullptr);
    /// The share of the points' stable steps the last rebuild carried over, in %.
    double
    steps_carried() const;
    /// The coupling band before the conversion of the cells marked now
    /// (Discretization::record_coupling()), with where their points will
    /// appear: within the buffer @p width, the margin and a converted
    /// cell's diameter of one of @p triggers (every rank's). Collective.
    PreviousCoupling
    coupling_before_conversion(std::vector<dealii::Point<dim>> triggers, const double width) const;
    /// A rank's families as they are, the far ends by key (a rebalance keeps
    /// those of the points that stay).
    struct OwnFamilies
    {
      std::vector<PointKey>     keys;  // the rank's points, owned first
      std::vector<unsigned int> order; // the owned ones' indices, sorted by key
      std::vector<std::size_t>  offsets;
      std::vector<unsigned int> neighbor; // indices into keys
      PreviousFamilies
      to_keep(const double extra_reach) const;
      /// For a conversion that moved the points first: these families, the
      /// changed points found against @p moved (the points this rank owns
      /// now, before the conversion).
      PreviousFamilies
      after_move(const Snapshot &moved, const double extra_reach) const;
    };
    /// A conversion that partitioned the mesh again before its rebuild.
    struct Moved
    {
      bool        moved     = false;
      double      imbalance = 0; // the work's, predicted for after the conversion
      double      seconds   = 0; // the move's
      double      reach     = 0; // the search's extra reach before the move
      OwnFamilies own;           // the families this rank had
    };
    /// The state before a conversion whose cells are marked: as it is, or,
    /// on several ranks with the work predicted out of balance by more than
    /// Rebalance threshold, moved to the ranks of a partition by that work
    /// (@p moved says so; one rebuild then serves both). Collective.
    Snapshot
    snapshot_for_conversion(Moved &moved);
    /// Sets each owned cell's weight (user index) to the work it will have
    /// after the conversion of the cells marked now: the points' bonds and a
    /// few per point (Discretization::set_cell_weights()), a converting
    /// cell's points (after their refinement) with the peridynamic block's
    /// mean family; returns how far the largest rank's work exceeds the
    /// mean. Collective.
    double
    predict_work_imbalance() const;
    /// Moves each owned cell's share of @p old (its points, bonds with their
    /// state, FE values and converted flag) to the rank that owns the cell
    /// after p4est partitioned the mesh by the cells' weights (user
    /// indices, recorded in the mesh history); returns what this rank
    /// received. Collective.
    Snapshot
    move_to_new_partition(Snapshot old);
    /// Takes the rank's families out of the Discretization (which a rebuild
    /// makes anew) with its points' keys.
    OwnFamilies
    take_own_families();
    /// Sets u and v of every owned point and FE DoF from @p old, then
    /// restore_bonds().
    void
    restore(const Snapshot &old);
    /// The FE cell of @p old that @p cell is or came from (a conversion
    /// refined it) and that cell's index in @p old, invalid if none.
    std::pair<unsigned int, dealii::Triangulation<dim>::cell_iterator>
    old_fe_cell(const Snapshot &old, const CellIterator &cell) const;
    /// u and v (dim each) of @p old's FE cell @p k (the cell @p source) at @p x.
    std::array<double, 2 * dim>
    interpolate(const Snapshot &old, const unsigned int k, const dealii::Triangulation<dim>::cell_iterator &source,
                const dealii::Point<dim> &x, const dealii::Mapping<dim> &mapping) const;
    /// The FE DoFs of the owned cells that stay FE, from @p old.
    void
    restore_fe_field(const Snapshot &old, const dealii::Mapping<dim> &mapping);
    /// After a conversion: if the ranks' work is out of balance by more than
    /// Rebalance threshold, partitions the mesh by it and moves each point,
    /// bond and FE cell with its state to its new rank (the points, bonds
    /// and parts made again as at a conversion). Collective.
    void
    rebalance(const double time);
    /// One owned cell's share of @p old (its points @p points, its FE
    /// values, its converted flag) as bytes, and back into @p moved on the
    /// cell's new owner (returns the converted flag).
    std::vector<char>
    pack_cell(const Snapshot &old, const std::vector<unsigned int> &points,
              const dealii::Triangulation<dim>::cell_iterator &cell, const bool converted) const;
    bool
    unpack_cell(Snapshot &moved, const dealii::Triangulation<dim>::cell_iterator &cell,
                const boost::iterator_range<std::vector<char>::const_iterator> &data) const;
    /// The received snapshot's key order and its FE cells in CellId order.
    void
    finish_moved(Snapshot &moved) const;
    /// The converted flags of the new partition: the owned cells' from
    /// @p owned_converted (the ids of those that came converted), the
    /// ghosts' from their owners. Collective.
    void
    set_converted_after_rebalance(std::vector<dealii::CellId> &owned_converted);
    /// After a rebalance: the FE values of the ghost FE cells from their
    /// owners into @p moved (restore_fe_field() needs them: an owned DoF
    /// may lie on ghost FE cells only), in CellId order again.
    void
    add_ghost_fe_cells(Snapshot &moved) const;
    /// The bond damage and the models' history from @p old; @p point_map:
    /// per owned point its old index (or -1).
    void
    restore_bonds(const Snapshot &old, const std::vector<unsigned int> &point_map);

    const AdaptivityParameters &parameters;
    Discretization             &discretization;
    ForceModel                 &model;
    Coupling                   &coupling;
    Postprocess                &post;
    MechanicalState            &state;
    RunRecord                  &record;
    MPI_Comm                    comm;
    dealii::ConditionalOStream &pcout;
    dealii::TimerOutput        &timer;
    std::function<void(double)>  rebuild; // at a time: the loads of then
    double                      critical_stretch = 0; // the PD block's s_c (strain and energy indicators)
    double                      wave_speed       = 0; // the fastest P wave of the convertible blocks
    unsigned int                interval         = 10;   // steps between checks (use_integrator())
    bool                        inertia          = true; // waves move between checks
    int                         target_level     = 0;    // Refine converted cells: the PD block's finest level
    MeshHistory                 history; // the conversions' refinement passes and rebalances
  };
} // namespace perideal
