// A template damage model: copy this file to source/damage/my_damage.cc,
// rename the class and the registered name, add the file to PERIDEAL_SOURCES
// in CMakeLists.txt (doc/developer/adding_a_model.md walks through it).
//
// The physics: a critical bond energy. Bond i-j breaks for good when it is
// stretched (s > 0) and its elastic energy w = c s^2 |xi| / 2 exceeds w_c,
// with c = 18 K / (pi delta^4) the bond-based micromodulus of the block's bulk
// modulus. w_c follows from the energy release rate: breaking every bond that
// crosses a unit area of a crack plane releases
//   G_c = 2 pi w_c int_0^delta int_z^delta (xi^2 - z xi) dxi dz = pi w_c delta^4 / 4,
// so w_c = 4 G_c / (pi delta^4), and a bond breaks past the stretch
//   s_c(|xi|) = sqrt(2 w_c / (c |xi|)) = sqrt(4 G_c / (9 K |xi|)):
// long bonds break first, unlike a critical stretch (one s_c for all).
// (The registered Critical energy model, source/damage/critical_energy.cc,
// is the full version: it takes each bond's energy from the block's material,
// Material::bond_energies(), so LPS's dilatation counts too.)
//
// Bond i->j and j->i are decided by their owners, from the positions both
// have, so both halves break in the same evaluation. Between blocks with
// different damage models (or different K) they would not: the core refuses
// a bond from a block with a law of its own to a block with another damage
// model (ForceModel::setup); critical_stretch.cc's BondStretchLimits shows
// how a stretch criterion decides such bonds alike.
//
// The state it keeps, to show a damage model's point_fields(): a local field,
// output "Bond energy ratio", the largest w / w_c over a point's intact bonds
// at the last damage pass (how close the point is to losing a bond).
//
// The file is compiled into the test suite (tests/models/CMakeLists.txt):
// models.templates runs a scene where it breaks bonds and checks each
// decision against s_c(|xi|).

#include <perideal/damage/damage_model.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class TemplateDamage : public DamageModel
    {
    public:
      // Keys, declared inside Damage models/NAME beside "Model".
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Critical energy release rate", "1", Patterns::Double(0),
                          "G_c; a bond breaks when its energy exceeds 4 G_c / (pi delta^4).");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path) override
      {
        release_rate = prm.get_double("Critical energy release rate");
        require_positive(release_rate, path + "/Critical energy release rate");
      }

      // Once per block: the material's moduli and the horizon fix the constants.
      void
      initialize(const Material &material, const double horizon) override
      {
        micromodulus    = 18 * material.bulk_modulus() / (M_PI * std::pow(horizon, 4));
        critical_energy = 4 * release_rate / (M_PI * std::pow(horizon, 4));
      }

      // Allocated by the core as a material's fields (field_store.h).
      std::vector<PointField>
      point_fields() const override
      {
        return {{"template_energy_ratio", FieldUse::local, 1, "Bond energy ratio"}};
      }

      // Breaks bonds of @p points (damage.broken[b] = 1, for good) and returns
      // how many broke now. Called before the material's force at every
      // evaluation that may break bonds; the implicit solvers call it once per
      // step. A binary model (continuous() false, the default) never sees
      // damage.damage; a continuous one raises it in place.
      std::size_t
      update(const ModelState &state, const std::vector<unsigned int> &points, const BondDamageArrays &damage) const override
      {
        std::size_t n = 0;
        with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
          n = update<decltype(periodic)::value>(state, points, damage.broken);
        });
        return n;
      }

      // Not a stretch criterion (stretch_criterion() is false by default), so
      // no material fuses this test into its bond loop and the core calls
      // update().

      // One line for the set-up report.
      std::string
      describe() const override
      {
        std::ostringstream out;
        out << "template critical bond energy w_c = " << critical_energy << " (G_c = " << release_rate << ")";
        return out.str();
      }

    private:
      double release_rate = 0, micromodulus = 0, critical_energy = 0;

      template <bool periodic>
      std::size_t
      update(const ModelState &state, const std::vector<unsigned int> &points, std::uint8_t *broken) const
      {
        const double *X     = state.cloud.X.data();
        VectorType   &ratio = state.fields.get("template_energy_ratio");
        std::size_t   n     = 0;
        for (const unsigned int i : points)
          {
            // bond_vectors(): both owners see the same lengths, so decide alike.
            const BondOrigin origin(X, state.u, i);
            double           largest = 0;
            for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
              {
                if (broken[b])
                  continue;
                double e[3], y[3];
                bond_vectors<periodic>(X, state.u, state.bonds.neighbor[b], origin, state.cloud.periodicity, e, y);
                const double r0 = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
                const double s  = (std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]) - r0) / r0;
                const double w  = s > 0 ? 0.5 * micromodulus * s * s * r0 : 0.0; // compression breaks nothing
                if (w > critical_energy)
                  {
                    broken[b] = 1;
                    ++n;
                  }
                else
                  largest = std::max(largest, w / critical_energy);
              }
            ratio.local_element(i) = largest;
          }
        return n;
      }
    };

    // Registered into the test programs that compile this file, not pd_app.
  } // namespace
  PERIDEAL_REGISTER(DamageModel, TemplateDamage, "Template damage",
                    "Template (doc/developer/templates): a bond breaks when its elastic energy "
                    "c s^2 |xi| / 2 exceeds 4 G_c / (pi delta^4). Keys: Critical energy release rate.")
} // namespace perideal
