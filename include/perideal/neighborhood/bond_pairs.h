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

#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace perideal
{
  /// Which bonds of a family a pair loop takes: the tail of a family inside
  /// the list (each bond for both ends), or of one that reaches outside (for
  /// both ends where the far end is in the list, else for i), or the head of
  /// one that reaches outside (for i where the far end is outside the list,
  /// else for neither: the far end takes it in its tail).
  /// A one-sided family (an extra point's) is all `own`: every bond for i
  /// alone.
  enum class PairPart
  {
    tail,
    masked_tail,
    head,
    own
  };

  /// Whether a part's bonds take a mask (which end each acts on depends on
  /// whether the far end is in the list), and whether any of them acts on
  /// the far end (a scatter).
  constexpr bool
  pair_masked(const PairPart part)
  {
    return part == PairPart::masked_tail || part == PairPart::head;
  }
  constexpr bool
  pair_scatters(const PairPart part)
  {
    return part == PairPart::tail || part == PairPart::masked_tail;
  }

  /// A pair loop's split of bond i -> j's force k y (per unit volume of
  /// the other end): k V_j on i, k V_i on j, each only where that end takes
  /// its share (selects, not products: 0 inf would be NaN); the far end's
  /// part goes to @p target, which is i (with +0) for a masked bond that
  /// acts on i alone. Inline: the pair loops stay vectorized.
  struct PairSplit
  {
    double       on_i, on_j;
    unsigned int target;
  };
  template <bool masked>
  inline PairSplit
  split_pair(const double k, const double Vi, const double Vj, const unsigned int i, const unsigned int j,
             const unsigned int on_i, const unsigned int on_j)
  {
    return {on_i != 0 ? k * Vj : 0.0, on_j != 0 ? k * Vi : 0.0, masked && on_j == 0 ? i : j};
  }

  /// Takes @p k y from the force of point @p target (3 per point).
  inline void
  scatter_pair_force(double *f, const unsigned int target, const double k, const double dx, const double dy,
                     const double dz)
  {
    f[3 * target] -= k * dx;
    f[3 * target + 1] -= k * dy;
    f[3 * target + 2] -= k * dz;
  }

  /// The share of bond i -> j each end takes in @p part, 1 or 0, given
  /// whether j is in the list (pair_masked() parts only); a kernel applies
  /// them as selects, not products (0 inf would be NaN).
  template <PairPart part>
  inline void
  pair_shares(const unsigned int listed, unsigned int &on_i, unsigned int &on_j)
  {
    on_i = part == PairPart::head ? 1 - listed : 1;
    on_j = part == PairPart::tail ? 1 : part == PairPart::masked_tail ? listed : 0;
  }

  /// Whether far end @p j is in a pair list of block @p block: an owned
  /// point (j < n_owned) of that block.
  inline bool
  pair_listed(const unsigned int j, const unsigned int n_owned, const unsigned int block,
              const unsigned short *block_of)
  {
    return j < n_owned && block_of[j] == block;
  }

  /// What every pair loop reads and writes, taken into one struct per
  /// kernel call; PMB's and LPS's PairData add their own fields.
  struct PairLoopData
  {
    Periodicity           box;
    const double         *X, *V, *u;
    const unsigned int   *neighbor;
    const unsigned short *block_of;
    std::uint8_t         *broken;   // breaking modes
    const std::uint8_t   *damage;   // binary damage (broken flags)
    double                limit;    // the squared limit (StretchBreaking) ...
    const double         *limit_at; // ... or by the far end's block
    const double         *d;        // continuous damage
    const double         *eps_T;    // heated only
    double               *f;
    unsigned int          n_owned, block;

    /// Whether far end @p j is in the list (pair_listed()).
    bool
    listed(const unsigned int j) const
    {
      return pair_listed(j, n_owned, block, block_of);
    }
  };

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

    /// Whether point @p j is in the list (@p block_of: the cloud's blocks).
    bool
    listed(const unsigned int j, const unsigned short *block_of) const
    {
      return pair_listed(j, n_owned, block, block_of);
    }

    /// Calls loop(part, i, from, last) for the parts of the family of each
    /// point i of the list (a std::integral_constant<PairPart, ...> and the
    /// bond range): the tail alone of a family inside the list, the head up
    /// to its last bond outside the list (head_end) and the masked tail of
    /// one that reaches outside. loop returns the halves
    /// it broke; with @p broken (breaking modes) the far end's half of a
    /// tail bond that broke is broken too. Returns the halves broken.
    template <typename Loop>
    std::size_t
    for_each_part(const PointCloud &cloud, const Bonds &bonds, const std::vector<unsigned int> &points,
                  std::uint8_t *broken, const Loop &loop) const
    {
      using Tail   = std::integral_constant<PairPart, PairPart::tail>;
      using Masked = std::integral_constant<PairPart, PairPart::masked_tail>;
      using Head   = std::integral_constant<PairPart, PairPart::head>;
      using Own    = std::integral_constant<PairPart, PairPart::own>;
      std::size_t newly_broken = 0;
      for (std::size_t k = 0; k < points.size(); ++k)
        {
          const unsigned int i     = points[k];
          const std::size_t  first = bonds.offsets[i], tail = first + upper[k], last = bonds.offsets[i + 1];
          if (broken != nullptr) // the tail's flags before: which of its bonds break now
            std::copy(broken + tail, broken + last, tail_before.begin());
          const std::size_t broke = mixed[k] == inside          ? loop(Tail(), i, tail, last) :
                                     mixed[k] == reaches_outside ? loop(Head(), i, first, first + head_end[k]) +
                                                                     loop(Masked(), i, tail, last) :
                                                                   loop(Own(), i, first, last);
          if (broken != nullptr && broke != 0)
            break_other_halves(cloud, bonds, i, tail, last, broken, tail_before.data());
          newly_broken += broke;
        }
      return newly_broken;
    }

    /// A tail bond of point i to a point of the list that broke now (set in
    /// @p broken, not in @p before, the tail's flags before) was evaluated
    /// for both ends: break the far end's half too. Only the new ones are
    /// looked up: a search per broken bond of the family was 10% of the
    /// LPS dmg cube's run.
    void
    break_other_halves(const PointCloud &cloud, const Bonds &bonds, unsigned int i, std::size_t tail,
                       std::size_t last, std::uint8_t *broken, const std::uint8_t *before) const;

    /// The index of bond j -> i in j's family (bonds are symmetric: i holds
    /// j exactly when j holds i). Binary search by key: for the other half
    /// of a bond that breaks.
    static std::size_t
    reverse(const PointCloud &cloud, const Bonds &bonds, unsigned int i, unsigned int j);

    /// Per point of the list (its place k): the offset within its family of
    /// the first bond whose far end's key is larger than the point's own.
    std::vector<unsigned int> upper;
    /// Per point of the list: one past the last bond of its family's head
    /// whose far end is outside the list (0 if none). A head's other bonds
    /// are evaluated by their far ends, so the head part stops there: on
    /// several ranks a family's ghosts of lower ranks are the first bonds
    /// of its head (the smaller keys), and the rest of the head, about a
    /// sixth of the bonds a rank evaluated (PMB cube, n = 40, 2 ranks), was
    /// evaluated only to be masked.
    std::vector<unsigned int> head_end;
    /// Per point of the list: reaches_outside if a far end of its family is
    /// not in the list (a ghost, or a point of another block): its bonds
    /// then take a mask, which end each one acts on; one_sided for an extra
    /// point, whose far ends do not hold it (its tail is empty).
    std::vector<std::uint8_t> mixed;
    static constexpr std::uint8_t inside = 0, reaches_outside = 1, one_sided = 2;
    /// The block, and the number of owned points: far end j is in the list
    /// if j < n_owned and its block is this one.
    unsigned int block   = 0;
    unsigned int n_owned = 0;

  private:
    const unsigned int *list = nullptr;
    /// for_each_part()'s copy of a tail's broken flags (the longest tail).
    mutable std::vector<std::uint8_t> tail_before;
  };
} // namespace perideal
