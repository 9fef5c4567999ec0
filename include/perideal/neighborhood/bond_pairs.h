#pragma once
// Each bond once (doc/performance.md, "Each pair once"): a bond kernel over
// the owned points of one block evaluates a bond between two of them once,
// at the end whose key is the smaller, and adds its force to both ends; a
// bond to any other point (a ghost, a point of another block) is evaluated
// by each end for itself, as with directed families. No bond array is
// added: each family is sorted by its far ends' keys (bonds.h), so the bonds
// a point evaluates for both ends are its family's tail, from `upper`.

#include <perideal/discretization/point_cloud.h>
#include <perideal/neighborhood/bonds.h>

#include <cstdint>
#include <vector>

namespace perideal
{
  class BondPairs
  {
  public:
    /// For the owned points @p points of block @p block (all of them, in
    /// their order): where each family's tail begins, and which families
    /// reach a point outside the list.
    void
    reinit(const PointCloud &cloud, const Bonds &bonds, const std::vector<unsigned int> &points, unsigned int block);

    /// Forget the list: kernels then evaluate every bond from both ends.
    void
    clear();

    /// True if reinit() was given @p points (the same vector, unchanged
    /// since): a kernel called with another list (a subset) must not use
    /// the tails.
    bool
    serves(const std::vector<unsigned int> &points) const
    {
      return list != nullptr && points.data() == list && points.size() == upper.size();
    }

    /// The index of bond j -> i in j's family (bonds are symmetric: i holds
    /// j exactly when j holds i). Binary search by key: for the other half
    /// of a bond that breaks.
    static std::size_t
    reverse(const PointCloud &cloud, const Bonds &bonds, unsigned int i, unsigned int j);

    /// Per point of the list (its place k): the offset within its family of
    /// the first bond whose far end's key is larger than the point's own.
    std::vector<unsigned int> upper;
    /// Per point of the list: 1 if a far end of its family is not in the
    /// list (a ghost, or a point of another block): its bonds then take a
    /// mask, which end each one acts on.
    std::vector<std::uint8_t> mixed;
    /// The block, and the number of owned points: far end j is in the list
    /// if j < n_owned and its block is this one.
    unsigned int block   = 0;
    unsigned int n_owned = 0;

  private:
    const unsigned int *list = nullptr;
  };
} // namespace perideal
