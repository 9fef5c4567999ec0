#pragma once
// Bond families in flat CSR form over the owned points: the bonds of owned
// point i are neighbor[offsets[i] .. offsets[i+1]), local point indices.
// Bond i->j and j->i are separate entries, each evaluated by its owner.
// Point i's family F(i) is the points within ITS horizon; with blocks of
// different horizons j may be in F(i) while i is not in F(j). A bond still
// acts on both ends (Peridigm), so the owner stores the union: j with j in
// F(i) or i in F(j), and `family` says which halves of each entry are real
// (see there). The union is symmetric, so i holds j exactly when j holds i.
// Each family is sorted by the neighbors' rank-independent keys, so sums over
// a family run in the same order on any number of ranks and a directed loop
// gives the same numbers on 1 and on N ranks (a pair loop, bond_pairs.h,
// agrees to round-off).

#include <perideal/discretization/point_cloud.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace perideal
{
  struct Bonds
  {
    std::vector<std::size_t>  offsets;  // n_owned + 1
    std::vector<unsigned int> neighbor; // local point index, one per bond

    /// Only when blocks of different horizons are bonded (empty otherwise,
    /// and every entry is in both families): per bond i->j, bit own_half if
    /// j is in F(i) (i's state sums over it and i's half of the bond acts),
    /// bit other_half if i is in F(j) (j's half acts on i). Kernels branch on
    /// family.empty() once, at compile time.
    std::vector<std::uint8_t> family;
    static constexpr std::uint8_t own_half = 1, other_half = 2;
    /// The horizon of each block, as find_families() used them.
    std::vector<double> block_horizon;
    /// Per owned point, 1 if it kept its family (find_families() with
    /// PreviousFamilies): those bonds passed the bond filters before, and
    /// need not again. Empty: none kept.
    std::vector<std::uint8_t> kept;
    /// The owned points that kept their families.
    unsigned int
    n_kept() const
    {
      return static_cast<unsigned int>(std::count(kept.begin(), kept.end(), std::uint8_t(1)));
    }

    /// 1 if bond @p b is in its owner's family, else 0 (set-up and reporting).
    double
    own(const std::size_t b) const
    {
      return family.empty() || (family[b] & own_half) ? 1.0 : 0.0;
    }

    std::size_t
    n_bonds() const
    {
      return neighbor.size();
    }

    /// beta_ij per bond, only with partial volumes (partial_volumes.h):
    /// neighbor j counts with volume beta_ij V_j.
    std::vector<float> volume_fraction;

    /// beta of bond @p b: 1 without partial volumes. For set-up and
    /// reporting; the force loops branch on volume_fraction.empty() once.
    double
    fraction(const std::size_t b) const
    {
      return volume_fraction.empty() ? 1.0 : volume_fraction[b];
    }

    /// Keeps the bonds (i, j) of the @p n_owned owned points for which
    /// @p keep(i, j) is true, in their order; frees the rest.
    template <typename Keep>
    void
    keep_if(const unsigned int n_owned, const Keep &keep)
    {
      keep_if_bond(n_owned, [&](const unsigned int i, const std::size_t b) { return keep(i, neighbor[b]); });
    }

    /// As keep_if(), with @p keep(i, b) given the owner and the bond's index.
    template <typename Keep>
    void
    keep_if_bond(const unsigned int n_owned, const Keep &keep)
    {
      const bool  fractions = !volume_fraction.empty(), halves = !family.empty();
      std::size_t kept      = 0;
      for (unsigned int i = 0; i < n_owned; ++i)
        {
          const std::size_t begin = offsets[i], end = offsets[i + 1];
          offsets[i]              = kept;
          for (std::size_t b = begin; b < end; ++b)
            if (keep(i, b))
              {
                if (fractions)
                  volume_fraction[kept] = volume_fraction[b];
                if (halves)
                  family[kept] = family[b];
                neighbor[kept++] = neighbor[b];
              }
        }
      offsets[n_owned] = kept;
      neighbor.resize(kept);
      neighbor.shrink_to_fit();
      if (fractions)
        {
          volume_fraction.resize(kept);
          volume_fraction.shrink_to_fit();
        }
      if (halves)
        {
          family.resize(kept);
          family.shrink_to_fit();
        }
    }
  };

  /// Relative tolerance of the horizon test: |xi| <= horizon * (1 + tol).
  constexpr double horizon_tolerance = 1e-9;

  /**
   * Finds the bonds of every owned point in the reference configuration
   * (R-tree over owned points and ghost candidates; point i's family is every
   * other point within horizon[block[i]] + @p extra_reach: the largest cell
   * radius when partial volumes follow; i stores the union of F(i) and the
   * points whose family holds i, and sets Bonds::family if some stored bond
   * joins different horizons on any rank), drops the ghost candidates no
   * bond uses and renumbers @p cloud. The points of a block b with
   * @p unbonded_block[b] != 0 (rigid blocks) take no bond, neither among
   * themselves nor to others. Collective.
   */
  /// The index i with keys[i] == @p key, found through @p order (the
  /// indices sorted by key), or numbers::invalid_unsigned_int.
  inline unsigned int
  find_by_key(const std::vector<PointKey> &keys, const std::vector<unsigned int> &order, const PointKey &key)
  {
    const auto it = std::lower_bound(order.begin(), order.end(), key,
                                     [&](const unsigned int a, const PointKey &k) { return keys[a] < k; });
    return it != order.end() && keys[*it] == key ? *it : dealii::numbers::invalid_unsigned_int;
  }

  /// The families of an earlier find_families() on the same scene, by
  /// identity, for a search after a change of some points (a conversion,
  /// doc/adaptivity.md): an owned point that existed before and lies
  /// farther than @p radius from every changed point keeps its family
  /// (mapped to the new indices) instead of being searched again.
  struct PreviousFamilies
  {
    const std::vector<PointKey>     *keys      = nullptr; // the old owned points
    const std::vector<unsigned int> *order     = nullptr; // their indices, sorted by key
    const std::vector<std::size_t>  *offsets   = nullptr; // their families' ranges in neighbor_index
    // Where the points changed is found by comparing the new owned points
    // with the old ones: these, or, after the points moved between ranks
    // (a conversion that rebalances), compared_keys and compared_order,
    // the points this rank owns now as they were before the change.
    const std::vector<double>       *positions = nullptr; // dim per compared point
    const std::vector<double>       *alpha     = nullptr; // the blending weight per compared point
    const std::vector<unsigned int> *block     = nullptr; // per compared point
    const std::vector<PointKey>     *compared_keys  = nullptr; // nullptr: keys
    const std::vector<unsigned int> *compared_order = nullptr; // nullptr: order
    const std::vector<std::uint8_t> *complete  = nullptr; // per old owned point, 0: its family is not all there (nullptr: all are)
    double                           extra_reach = 0;     // the earlier search's (none kept if it differs)
    // Each bond's far end as an index into index_keys (the rank's points
    // then), each family sorted by the far ends' keys: 4 bytes a bond, and
    // one look-up per point of index_keys rather than one per bond.
    const std::vector<unsigned int> *neighbor_index = nullptr;
    const std::vector<PointKey>     *index_keys     = nullptr;
    // A rebalance: no point changed place, block or weight, so no family
    // changed; only those of the points new to the rank are searched.
    bool nothing_moved = false;
    // Filled by the Discretization from the new points: where points
    // appeared, vanished or changed (every rank's), and the search reach.
    std::vector<dealii::Point<dim>> changed;
    double                          radius = 0;
  };

  Bonds
  find_families(PointCloud                      &cloud,
                const std::vector<double>       &block_horizon,
                const MPI_Comm                   comm,
                const double                     extra_reach    = 0,
                const std::vector<std::uint8_t> &unbonded_block = {},
                const PreviousFamilies          *previous       = nullptr);
} // namespace perideal
