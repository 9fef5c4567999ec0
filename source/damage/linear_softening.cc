// Linear softening (the bilinear bond law of cohesive peridynamics, e.g.
// Gerstle, Sau and Silling, Nucl. Eng. Des. 237 (2007) 1250; Niazi, Chen and
// Bobaru, Theor. Appl. Fract. Mech. 112 (2021) 102855): the bond force rises
// linearly with the stretch s up to the onset stretch s_0, then falls
// linearly to zero at the critical stretch s_c:
//   f(s) = c s                                   s <= s_0
//   f(s) = c s_0 (s_c - s) / (s_c - s_0)         s_0 < s < s_c
//   f(s) = 0                                     s >= s_c.
// As a damage d in f = (1 - d) c s, with s_max the largest stretch the bond
// has seen:
//   d = s_c (s_max - s_0) / (s_max (s_c - s_0)),  clamped to [0, 1],
// so unloading follows the secant (1 - d) c s back to the origin, and
// compression too. d is a non-decreasing function of s_max, so the largest d
// so far is d(s_max): the update d = max(d, d(s)) keeps it, and no s_max is
// stored (the core runs the update only on the states a run keeps,
// DamageModel::update()). The energy a bond
// dissipates until it breaks is the area under f: c s_0 s_c / 2 (critical
// stretch: c s_c^2 / 2), so the PMB fracture energy is
// G = 9 K s_0 s_c delta / 5.
// Both owners compute s from the same lengths (bond_vectors()) and start
// from the same d, so both halves of a bond get the same d bit for bit.

#include <perideal/damage/damage_model.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class LinearSoftening : public DamageModel
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Onset stretch", "0", Patterns::Double(0),
                          "s_0: the stretch of the peak force c s_0, where softening starts.");
        prm.declare_entry("Critical stretch", "0", Patterns::Double(0),
                          "s_c > s_0: the stretch where the force has fallen to zero and the bond is broken.");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path) override
      {
        s0 = prm.get_double("Onset stretch");
        sc = prm.get_double("Critical stretch");
        AssertThrow(s0 > 0 && s0 < sc,
                    ExcMessage(path + ": 'Onset stretch' (" + prm.get("Onset stretch") + ") and 'Critical stretch' (" +
                               prm.get("Critical stretch") + ") must satisfy 0 < Onset stretch < Critical stretch"));
      }

      void
      initialize(const Material &, const double) override
      {}

      bool
      continuous() const override
      {
        return true;
      }

      std::size_t
      update(const ModelState &state, const std::vector<unsigned int> &points, const BondDamageArrays &damage) const override
      {
        std::size_t n = 0;
        with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
          n = update<decltype(periodic)::value>(state, points, damage);
        });
        return n;
      }

      std::string
      describe() const override
      {
        std::ostringstream out;
        out << "linear softening from s_0 = " << std::setprecision(6) << s0 << " to s_c = " << sc;
        return out.str();
      }

    private:
      double s0 = 0, sc = 0;

      template <bool periodic>
      std::size_t
      update(const ModelState &state, const std::vector<unsigned int> &points, const BondDamageArrays &damage) const
      {
        const Periodicity   box      = state.cloud.periodicity;
        const double       *X        = state.cloud.X.data();
        const double       *u        = state.u;
        const std::size_t  *offsets  = state.bonds.offsets.data();
        const unsigned int *neighbor = state.bonds.neighbor.data();
        double             *d        = damage.damage;
        std::uint8_t       *broken   = damage.broken;
        const double        scale    = sc / (sc - s0);
        // Below the onset (most bonds, most of the time) the law is 0 and d
        // keeps its value: a test in squared lengths, no square root or
        // division, skips them. The margin leaves the bonds within round-off
        // of the onset to the formula, so the decisions are those of the
        // formula for every bond.
        const double below = (1 + s0) * (1 + s0) * (1 - 1e-12);
        std::size_t  rose  = 0;
        for (const unsigned int i : points)
          {
            const BondOrigin origin(X, u, i);
            for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
              {
                double e[3], y[3];
                bond_vectors<periodic>(X, u, neighbor[b], origin, box, e, y);
                const double e_sq = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
                const double y_sq = y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
                if (y_sq < below * e_sq)
                  continue;
                const double r0 = std::sqrt(e_sq);
                const double r  = std::sqrt(y_sq);
                const double s  = (r - r0) / r0;
                // 0 up to s_0 (no division by a small or negative s); exactly 1
                // from s_c on, whatever the rounding of the formula there.
                const double law  = s >= sc ? 1.0 : std::min(scale * (1 - s0 / std::max(s, s0)), 1.0);
                const double next = std::max(d[b], law);
                rose += next > d[b];
                d[b] = next;
                broken[b] |= next == 1.0;
              }
          }
        return rose;
      }
    };
  } // namespace

  PERIDEAL_REGISTER(DamageModel, LinearSoftening, "Linear softening",
                    "Bilinear bond law: the bond force c s rises to c s_0 at the onset stretch s_0, then falls "
                    "linearly to zero at the critical stretch s_c (a continuous bond damage d = s_c (s_max - s_0) / "
                    "(s_max (s_c - s_0)), s_max the largest stretch so far; unloading follows the secant (1 - d) c s). "
                    "Each bond dissipates c s_0 s_c / 2 (PMB: G = 9 K s_0 s_c horizon / 5). PMB and LPS; a block "
                    "with it bonds only to blocks with the same damage model.")
} // namespace perideal
