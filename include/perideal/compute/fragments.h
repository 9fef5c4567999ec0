#pragma once
// Fragments (Output/Fragments and the Fragment field): the pieces the bodies
// have broken into, the connected components of the intact bonds.
//
// - Two points are in one fragment if a chain of intact bonds joins them
//   (a bond counts if either of its halves is intact; a bond whose continuous
//   damage is below 1 is intact). The points of a rigid block are one
//   fragment. A point that has lost every bond is a fragment of its own.
// - Found across ranks: a union-find over each rank's points and the ghosts
//   its bonds reach, then the smallest global point index of each component
//   spread through the ghosts until no rank changes one (as many rounds as a
//   fragment crosses rank boundaries in a chain, plus one).
// - Fragments are numbered 0, 1, ... in the order of their smallest global
//   point index, so a run gives the same numbers on any number of ranks.
// - Only points with mass count: the virtual points of the FE-PD coupling
//   join the fragments their bonds reach (through them a fragment stays
//   attached to the continuum) but add no mass and no point; a component of
//   virtual points alone is no fragment (number -1).

#include <perideal/discretization/point_cloud.h>
#include <perideal/material/field_store.h>
#include <perideal/model/block.h>
#include <perideal/neighborhood/bonds.h>

#include <cstdint>
#include <vector>

namespace perideal
{
  struct Fragments
  {
    /// Per owned point: its fragment's number, or -1 (see above).
    std::vector<double> number;
    std::size_t         count = 0;

    /// On rank 0 only: the fragments in number order.
    struct Row
    {
      double smallest_point = 0; // the smallest global point index in it
      double points = 0, mass = 0, momentum[3] = {0, 0, 0}, kinetic_energy = 0;
    };
    std::vector<Row> rows;
  };

  /// The fragments of the current state. @p broken: per bond (empty without
  /// damage); @p mass_density per owned point (0 at virtual points);
  /// @p velocity dim entries per owned point. Collective.
  Fragments
  find_fragments(const PointCloud &cloud, const Bonds &bonds, const std::vector<std::uint8_t> &broken,
                 const std::vector<Block> &blocks, const std::vector<double> &mass_density, const VectorType &velocity,
                 const MPI_Comm comm);
} // namespace perideal
