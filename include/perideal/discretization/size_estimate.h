#pragma once
// The size of a scene before it is built: cells, points, bonds and the
// memory they take, compared with the memory the ranks have (Simulation::setup
// checks it before the mesh is made and before each refinement), so that a
// scene too large ends in an Error naming the key that makes it large
// instead of std::bad_alloc, a p4est abort or the kernel's OOM killer.
//
// Every count is a lower bound of what the set-up will build (a scene that
// fits is never refused): the cells are exact, the points count only the
// cells that surely become peridynamic points, the bonds only the pairs
// surely within the horizon.

#include <perideal/base/memory.h>

#include <deal.II/base/conditional_ostream.h>

#include <array>
#include <string>

namespace perideal
{
  /// Bytes of the set-up's data structures, measured with --dry-run on boxes
  /// (doc: the numbers in source/discretization/size_estimate.cc), rounded
  /// down so that the estimate stays a lower bound.
  struct SizeCosts
  {
    static constexpr double coarse_cell = 1000; // a coarse cell, on every rank (deal.II + p4est connectivity)
    static constexpr double cell        = 450;  // an active cell (deal.II levels, p4est quadrant, DoFs)
    static constexpr double point       = 160;  // a point (cloud, fields, vectors)
    static constexpr double bond        = 4;    // a directed bond (neighbor index; more with damage/partial volumes)
  };

  struct SizeEstimate
  {
    double coarse_cells = 0; // the coarse mesh, held whole by every rank
    double cells        = 0; // active cells, all ranks
    double points       = 0; // peridynamic points, all ranks (lower bound)
    double bonds        = 0; // directed bonds, all ranks (lower bound)

    /// What one of @p ranks ranks needs (the coarse mesh whole, the rest shared).
    double
    bytes_per_rank(const unsigned int ranks) const
    {
      return coarse_cells * SizeCosts::coarse_cell +
             (cells * SizeCosts::cell + points * SizeCosts::point + bonds * SizeCosts::bond) / ranks;
    }
  };

  /// The ordered pairs of distinct points within @p delta of each other in a
  /// lattice of n[0] x n[1] x n[2] points with spacings h (a box's cell
  /// centroids): exact up to the blocking of long rows, where it is a lower
  /// bound. Milliseconds for any size.
  double
  lattice_pairs(const std::array<double, 3> &n, const std::array<double, 3> &h, const double delta);

  /// The largest number of cells (and points) the 32-bit indices of this
  /// deal.II build can count: 3 DoFs per cell must fit in
  /// types::global_dof_index.
  double
  max_countable_cells();

  /// Makes p4est's abort on a failed allocation (a scene between the lower
  /// bound of the estimate and the memory there is) end the run with an
  /// Error line and exit code 1 instead of SIGABRT and a backtrace.
  void
  report_p4est_out_of_memory();

  /// Stops with an Error if @p estimate does not fit in @p available or
  /// overflows the indices; with @p print (dry runs) prints the estimate to
  /// @p out first. @p what names the stage ("the scene", "refinement level
  /// 3"), @p cells_key the keys that set the cells, @p horizon_key those
  /// that set the bonds per point. Every rank must call it with the same
  /// arguments (it throws on all or none).
  void
  check_size(const SizeEstimate             &estimate,
             const AvailableMemory          &available,
             const unsigned int              ranks,
             const std::string              &what,
             const std::string              &cells_key,
             const std::string              &horizon_key,
             const bool                      print,
             const dealii::ConditionalOStream &out);
} // namespace perideal
