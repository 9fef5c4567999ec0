// Critical stretch (Silling and Askari 2005): bond i-j breaks for good when
// its stretch s = (|y_j - y_i| - |xi|)/|xi| exceeds s_c. s_c is given, or
// derived from the critical energy release rate G_c of the PMB material:
//   s_c = sqrt(5 G_c / (9 K delta)).
// Both owners compute the same s from the same positions, so both halves of
// a bond break in the same step. Across blocks a bond breaks at the smaller
// s_c of its two blocks' stretch criteria (an Interface aware block gives its
// interfaces a value of their own); a block without one does
// not protect its bonds to a block with one, and a bond between two blocks
// without one never breaks (BondStretchLimits in damage_model.h: the core
// applies it, so both halves of a bond are decided alike).
// A material that fuses the test into its first bond pass (PMB, LPS: see
// Material::fuses_stretch_criterion()) applies exactly this test there, and
// the core skips update() for its block: one pass over the bonds, not two.
// PMB and LPS do so also where a block's bonds break at different limits (by the
// far end's block, Material::fuses_limits_by_block()): a continuum block's
// virtual points beside a PD block, or blocks of different s_c.

#include <perideal/damage/damage_model.h>

#include <deal.II/base/utilities.h>

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class CriticalStretch : public StretchCriterion
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Critical stretch", "0", Patterns::Double(),
                          "s_c. 0: derive it from the critical energy release rate.");
        prm.declare_entry("Critical energy release rate", "0", Patterns::Double(),
                          "G_c, used when Critical stretch is 0: s_c = sqrt(5 G_c / (9 K delta)).");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path_) override
      {
        path         = path_;
        given_sc     = prm.get_double("Critical stretch");
        release_rate = prm.get_double("Critical energy release rate");
        // Checked here, not by the key's pattern: the parser's message names no section.
        for (const auto &[key, value] : {std::make_pair("Critical stretch", given_sc),
                                         std::make_pair("Critical energy release rate", release_rate)})
          AssertThrow(value >= 0, ExcMessage(path + "/" + key + " must be >= 0 (0: not given), got " + prm.get(key)));
        AssertThrow(given_sc > 0 || release_rate > 0,
                    ExcMessage(path + ": set 'Critical stretch' or 'Critical energy "
                                      "release rate' to a positive value"));
        // With both, the release rate was silently ignored.
        AssertThrow(given_sc == 0 || release_rate == 0,
                    ExcMessage(path + ": both 'Critical stretch' (" + prm.get("Critical stretch") +
                               ") and 'Critical energy release rate' (" + prm.get("Critical energy release rate") +
                               ") are set, and the release rate would be ignored: set one of them (the "
                               "stretch follows from the release rate as sqrt(5 G_c / (9 K horizon)))"));
      }

      void
      initialize(const Material &material, const double horizon) override
      {
        sc = given_sc > 0 ?
               given_sc :
               std::sqrt(5 * release_rate / (9 * material.bulk_modulus() * horizon));
      }

      double
      critical_stretch(const double) const override
      {
        return sc;
      }

      std::string
      describe() const override
      {
        std::ostringstream out;
        out << "critical stretch s_c = " << std::setprecision(6) << sc;
        if (given_sc == 0)
          out << " (from G_c = " << release_rate << ")";
        return out.str();
      }

    private:
      std::string path;
      double      given_sc = 0, release_rate = 0, sc = 0;
    };
  } // namespace

  PERIDEAL_REGISTER(DamageModel, CriticalStretch, "Critical stretch",
                    "Bond breaks when its stretch exceeds s_c (given, or from G_c). A bond between "
                    "two blocks breaks at the smaller s_c of the two blocks' critical-stretch models; "
                    "a block without damage model does not protect its bonds to one with this model.")

  BondStretchLimits::BondStretchLimits(const unsigned int n_blocks_,
                                       const PointCloud  &cloud,
                                       const Bonds       &bonds,
                                       const MPI_Comm     comm)
    : n_blocks(n_blocks_)
  {
    reaches.assign(n_blocks * n_blocks, 0);
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
        reaches[cloud.block[i] * n_blocks + cloud.block[bonds.neighbor[b]]] = 1;
    Utilities::MPI::max(reaches, comm, reaches);
    set(std::vector<double>(n_blocks, 0.0), std::vector<double>(n_blocks, 0.0));
  }

  void
  BondStretchLimits::set(const std::vector<double> &within, const std::vector<double> &across)
  {
    const double never = std::numeric_limits<double>::infinity();
    pair.assign(n_blocks * n_blocks, never);
    for (unsigned int a = 0; a < n_blocks; ++a)
      for (unsigned int b = 0; b < n_blocks; ++b)
        for (const double sc : {a == b ? within[a] : across[a], a == b ? within[a] : across[b]})
          if (sc > 0)
            pair[a * n_blocks + b] = std::min(pair[a * n_blocks + b], stretch_squared_limit(sc));
    // A block's bonds share one limit if every block they reach (on any
    // rank) gives the same.
    common.assign(n_blocks, 0.0);
    breaking.assign(n_blocks, false);
    for (unsigned int k = 0; k < n_blocks; ++k)
      {
        double lowest = never, highest = -never;
        for (unsigned int b = 0; b < n_blocks; ++b)
          if (reaches[k * n_blocks + b])
            {
              lowest  = std::min(lowest, pair[k * n_blocks + b]);
              highest = std::max(highest, pair[k * n_blocks + b]);
            }
        breaking[k] = lowest < never;
        if (breaking[k] && lowest == highest)
          common[k] = lowest;
      }
  }

  namespace
  {
    template <bool periodic>
    std::size_t
    break_by_pair(const ModelState                &state,
                  const std::vector<unsigned int> &points,
                  const double                    *pair,
                  const unsigned int               n_blocks,
                  std::uint8_t                    *broken)
    {
      const Periodicity    box      = state.cloud.periodicity;
      const double        *X        = state.cloud.X.data();
      const double        *u        = state.u;
      const std::size_t   *offsets  = state.bonds.offsets.data();
      const unsigned int  *neighbor = state.bonds.neighbor.data();
      const unsigned short *block   = state.cloud.block.data();
      std::size_t          n        = 0;
      for (const unsigned int i : points)
        {
          const BondOrigin origin(X, u, i);
          const double    *limit = pair + block[i] * n_blocks;
          for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
            {
              double e[3], y[3];
              bond_vectors<periodic>(X, u, neighbor[b], origin, box, e, y);
              n += break_if_overstretched(y[0] * y[0] + y[1] * y[1] + y[2] * y[2],
                                          e[0] * e[0] + e[1] * e[1] + e[2] * e[2],
                                          limit[block[neighbor[b]]],
                                          broken[b]);
            }
        }
      return n;
    }
    template <bool periodic>
    std::size_t
    break_beyond(const ModelState &state, const std::vector<unsigned int> &points, const double sc, std::uint8_t *broken)
    {
      const Periodicity   box      = state.cloud.periodicity;
      const double       *X        = state.cloud.X.data();
      const double       *u        = state.u;
      const std::size_t  *offsets  = state.bonds.offsets.data();
      const unsigned int *neighbor = state.bonds.neighbor.data();
      // Compare squared lengths: |y| > (1 + s_c)|xi|, no square root per bond.
      const double factor = stretch_squared_limit(sc);
      std::size_t  n      = 0;
      for (const unsigned int i : points)
        {
          const BondOrigin origin(X, u, i);
#pragma omp simd reduction(+ : n)
          for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
            {
              double e[3], y[3];
              bond_vectors<periodic>(X, u, neighbor[b], origin, box, e, y);
              n += break_if_overstretched(y[0] * y[0] + y[1] * y[1] + y[2] * y[2],
                                          e[0] * e[0] + e[1] * e[1] + e[2] * e[2],
                                          factor,
                                          broken[b]);
            }
        }
      return n;
    }
  } // namespace

  std::size_t
  break_overstretched(const ModelState                &state,
                      const std::vector<unsigned int> &points,
                      const double                     critical_stretch,
                      std::uint8_t                    *broken)
  {
    std::size_t n = 0;
    with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
      n = break_beyond<decltype(periodic)::value>(state, points, critical_stretch, broken);
    });
    return n;
  }

  std::size_t
  BondStretchLimits::update(const ModelState &state, const std::vector<unsigned int> &points, std::uint8_t *broken) const
  {
    std::size_t n = 0;
    with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
      n = break_by_pair<decltype(periodic)::value>(state, points, pair.data(), n_blocks, broken);
    });
    return n;
  }
} // namespace perideal
