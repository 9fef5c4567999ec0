// Von Mises stress damage (Peridigm's "Von Mises Stress" damage model), for
// the correspondence materials, whose points carry a Cauchy stress: a bond's
// damage follows the von Mises stress of its two ends,
//   sigma_b = (sigma_vm,i + sigma_vm,j) / 2,
//   d = clamp((sigma_b / sigma_c - r_0) / (r_1 - r_0), 0, 1),   d never decreases,
// with sigma_c the Critical von Mises stress, r_0 the Threshold damage and
// r_1 the Critical damage (Peridigm's names: stress ratios where damage
// starts and where the bond is broken; Peridigm's defaults 0.99 and 1, a
// nearly brittle break at sigma_c). Peridigm takes a bond-level stress of
// its bond-associated models; the mean of the two ends is the same for both
// owners of the bond, so both halves always carry the same d.
// The von Mises stresses are the material's stage field corr_von_mises of
// the evaluation before (the damage pass runs first,
// ForceModel::compute_forces()), ghosts included: a lag of one explicit
// step, none after an implicit step's converged solve (break_bonds()).

#include <perideal/damage/damage_model.h>

#include <algorithm>
#include <iomanip>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  // Local to this file: a plugin class whose name another file also uses
  // (the compute quantity "Von Mises stress") would be one class to the
  // linker, with one of the two vtables for both.
  namespace
  {
  class VonMisesStress : public DamageModel
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry("Critical von Mises stress", "0", Patterns::Double(),
                        "Von Mises stress: sigma_c > 0, the stress the damage ratios refer to.");
      prm.declare_entry("Threshold damage", "0.99", Patterns::Double(),
                        "Von Mises stress: r_0, the ratio sigma / sigma_c of a bond's mean end stress where its "
                        "damage starts to rise (Peridigm's name and default).");
      prm.declare_entry("Critical damage", "1", Patterns::Double(),
                        "Von Mises stress: r_1 > r_0, the ratio where the bond is broken; in between d rises "
                        "linearly (Peridigm's name and default).");
    }

    void
    parse_parameters(ParameterHandler &prm, const std::string &path_) override
    {
      path     = path_;
      critical = prm.get_double("Critical von Mises stress");
      onset    = prm.get_double("Threshold damage");
      full     = prm.get_double("Critical damage");
      AssertThrow(critical > 0, ExcMessage(path + "/Critical von Mises stress must be positive, got " +
                                           prm.get("Critical von Mises stress")));
      AssertThrow(onset >= 0 && onset < full,
                  ExcMessage(path + ": Threshold damage (" + prm.get("Threshold damage") + ") and Critical damage (" +
                             prm.get("Critical damage") + ") must satisfy 0 <= Threshold damage < Critical damage"));
    }

    void
    initialize(const Material &material, const double) override
    {
      const auto fields = material.point_fields();
      AssertThrow(std::any_of(fields.begin(), fields.end(),
                              [](const PointField &f) { return f.name == "corr_von_mises"; }),
                  ExcMessage(path + ": Von Mises stress damage needs a stress at every point, which only the "
                                    "correspondence materials have (Elastic correspondence, Elastic plastic "
                                    "correspondence); this block's material has none"));
    }

    bool
    continuous() const override
    {
      return true;
    }

    std::size_t
    update(const ModelState &state, const std::vector<unsigned int> &points, const BondDamageArrays &damage) const override
    {
      const double       *vm       = state.fields.get("corr_von_mises").begin();
      const std::size_t  *offsets  = state.bonds.offsets.data();
      const unsigned int *neighbor = state.bonds.neighbor.data();
      double             *d        = damage.damage;
      std::uint8_t       *broken   = damage.broken;
      // d = (sigma_b / sigma_c - r_0) / (r_1 - r_0), with sigma_b the mean of the ends.
      const double scale = 0.5 / (critical * (full - onset)), shift = onset / (full - onset);
      std::size_t  rose  = 0;
      for (const unsigned int i : points)
        for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
          {
            const double law = std::min((vm[i] + vm[neighbor[b]]) * scale - shift, 1.0);
            if (!(law > d[b])) // (a NaN stress raises nothing)
              continue;
            d[b] = law;
            ++rose;
            broken[b] |= law == 1.0;
          }
      return rose;
    }

    std::string
    describe() const override
    {
      std::ostringstream out;
      out << std::setprecision(6) << "von Mises stress sigma_c = " << critical << ", damage from " << onset
          << " sigma_c to " << full << " sigma_c";
      return out.str();
    }

  private:
    std::string path;
    double      critical = 0, onset = 0.99, full = 1;
  };
  } // namespace

  PERIDEAL_REGISTER(DamageModel, VonMisesStress, "Von Mises stress",
                    "Peridigm's Von Mises Stress damage, for the correspondence materials: a bond's damage rises "
                    "linearly from 0 to 1 as the mean von Mises stress of its two ends goes from Threshold damage "
                    "x to Critical damage x Critical von Mises stress, and never decreases.")
} // namespace perideal
