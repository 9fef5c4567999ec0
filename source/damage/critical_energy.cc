// Critical energy (energy-based failure; Foster, Silling and Chen, Int. J.
// Multiscale Comput. Eng. 9 (2011) 675): bond i-j breaks for good when it is
// stretched (|y| > |xi|) and its energy w exceeds the critical bond energy
//   w_c = 4 G_c / (pi delta^4).
// Why this w_c: a crack plane separates every bond that crosses it, and the
// bonds of unit volumes at distance z on either side of a unit area that
// cross it number, per unit V_i V_j, 2 pi int_z^delta (xi^2 - z xi) dxi, so
// breaking them all, each at w_c, releases
//   G = int_0^delta 2 pi w_c int_z^delta (xi^2 - z xi) dxi dz = pi w_c delta^4 / 4.
// w is the material's (Material::bond_energies()): the work of the bond's
// pairwise force along its extension, per unit volume of each end. The
// families (doc/models.md derives each):
//   PMB  w = c s^2 |xi| / 2, so a bond breaks past s_c(|xi|) = sqrt(4 G_c / (9 K |xi|)):
//        long bonds first; the same G_c as Critical stretch's sqrt(5 G_c / (9 K delta))
//        for the bonds of a crack plane on the whole, not bond by bond.
//   LPS  w = (t_ij + t_ji) e / 2, the scalar force state of both halves times the
//        extension: the dilatation of both ends counts, so a bond in a point under
//        hydrostatic tension stores more than the same stretch in shear.
//   Elastic plastic, Viscoelastic: w = int (t_ij + t_ji) de, the work the pair
//        force has done along the bond's extension so far (ordinary_state.h:
//        per-bond history, trapezoid rule per step), stored and dissipated:
//        plastic flow or a dashpot that takes energy brings the bond nearer
//        to breaking, as in Foster et al.'s work-based criterion.
//   Correspondence (Elastic, Elastic plastic): w = int (T_ij - T_ji) . d(u_j - u_i),
//        the work of the pair's force, which is not along the bond, along the
//        relative displacement (correspondence.h: per-bond history, trapezoid
//        rule per step), stabilization included.
// Summed over the pairs (w V_i V_j), w is the strain energy exactly for PMB
// and LPS, and the stored energy plus the dissipation (to the trapezoid rule's
// error) for the path-dependent ones, so a fully split specimen releases what
// the bonds across it took and G_c per area.
// The stage fields (LPS's dilatation terms) are those of the evaluation
// before (the damage pass runs first, ForceModel::compute_forces()): both
// owners of a bond read the same values, ghosts included, so both halves
// break in the same evaluation; the lag is one step of an explicit run, none
// after an implicit step's converged solve (break_bonds()). The bond work of
// the inelastic models is the last evaluation's likewise.
// Compression breaks nothing. The critical energy depends on the horizon,
// so blocks of different horizons may not share bonds under it (the core
// refuses them, horizon_dependent()).

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
    class CriticalEnergy : public DamageModel
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Critical energy release rate", "0", Patterns::Double(),
                          "G_c > 0: a stretched bond breaks when its energy (for Elastic plastic, Viscoelastic and "
                          "the correspondence models: the work done on it, stored and dissipated) exceeds "
                          "w_c = 4 G_c / (pi horizon^4).");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path_) override
      {
        path         = path_;
        release_rate = prm.get_double("Critical energy release rate");
        AssertThrow(release_rate > 0, ExcMessage(path + "/Critical energy release rate must be positive, got " +
                                                 prm.get("Critical energy release rate")));
      }

      bool
      uses_bond_energy() const override
      {
        return true;
      }

      void
      initialize(const Material &material_, const double horizon) override
      {
        AssertThrow(material_.has_bond_energy(),
                    ExcMessage(path + ": Critical energy breaks a bond by its energy, which this block's material "
                                      "does not define"));
        material        = &material_;
        critical_energy = 4 * release_rate / (M_PI * std::pow(horizon, 4));
      }

      std::vector<PointField>
      point_fields() const override
      {
        return {{"critical_energy_ratio", FieldUse::local, 1, "Critical energy ratio"}};
      }

      bool
      horizon_dependent() const override
      {
        return true;
      }

      std::size_t
      update(const ModelState &state, const std::vector<unsigned int> &points, const BondDamageArrays &damage) const override
      {
        std::size_t n = 0;
        with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
          n = update<decltype(periodic)::value>(state, points, damage.broken);
        });
        return n;
      }

      std::string
      describe() const override
      {
        std::ostringstream out;
        out << "critical energy w_c = " << std::setprecision(6) << critical_energy << " (G_c = " << release_rate
            << ")";
        return out.str();
      }

    private:
      std::string         path;
      double              release_rate = 0, critical_energy = 0;
      const Material     *material = nullptr;
      mutable std::vector<double> energy; // one family's bond energies; grows to the largest family

      template <bool periodic>
      std::size_t
      update(const ModelState &state, const std::vector<unsigned int> &points, std::uint8_t *broken) const
      {
        const double *X     = state.cloud.X.data();
        double       *ratio = state.fields.get("critical_energy_ratio").begin();
        std::size_t   n     = 0;
        for (const unsigned int i : points)
          {
            const std::size_t first = state.bonds.offsets[i], size = state.bonds.offsets[i + 1] - first;
            if (energy.size() < size)
              energy.resize(size);
            material->bond_energies(state, i, energy.data());
            // Only a bond above the point's largest ratio so far can break or
            // raise it (ratios of bonds that did not break are <= 1), so the
            // test for tension, which needs the bond's lengths, runs for few.
            const BondOrigin origin(X, state.u, i);
            double           largest = 0;
            for (std::size_t k = 0; k < size; ++k)
              {
                const std::size_t b = first + k;
                if (broken[b] || !(energy[k] > largest * critical_energy))
                  continue;
                double e[3], y[3];
                bond_vectors<periodic>(X, state.u, state.bonds.neighbor[b], origin, state.cloud.periodicity, e, y);
                if (!(y[0] * y[0] + y[1] * y[1] + y[2] * y[2] > e[0] * e[0] + e[1] * e[1] + e[2] * e[2]))
                  continue; // compression breaks nothing
                if (energy[k] > critical_energy)
                  {
                    broken[b] = 1;
                    ++n;
                  }
                else
                  largest = energy[k] / critical_energy;
              }
            ratio[i] = largest;
          }
        return n;
      }
    };
  } // namespace

  PERIDEAL_REGISTER(DamageModel, CriticalEnergy, "Critical energy",
                    "A stretched bond breaks when its energy (the work of its pairwise force along its extension, "
                    "the material's; for Elastic plastic, Viscoelastic and the correspondence models the work "
                    "done on it so far, stored and dissipated) exceeds w_c = 4 G_c / (pi horizon^4) (Foster et "
                    "al. 2011). Every material; a block with it bonds only to blocks with the same damage model "
                    "and horizon.")
} // namespace perideal
