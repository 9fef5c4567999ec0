// Material::released_energy(), what Solver/Track dissipated energy sums: the
// strain energy a change of bond damage releases, sum_i V_i (W_i(before) -
// W_i(now)) at one displacement.
//
// Unit cube, 8^3 points, horizon 3.015 h, a random displacement of amplitude
// 3e-3 (the same on any number of ranks). Before: 5% of the bonds broken
// (continuous damage: every bond at a random d in [0, 0.3]); now: another
// 10% broken (d raised by up to 0.4 on 20% of the bonds), both halves of a
// bond alike. For every variant of PMB and LPS (omega = 1 and 1 - r, the
// surface corrections, partial volumes, a periodic box, a temperature field,
// two blocks of different horizons, continuous damage, an energy weight as
// the FE coupling sets it), whose released_energy() sums over the bonds in
// one pass without evaluating the points, checked:
// 1. it equals the difference of two whole evaluations, sum_i V_i W_i with
//    the damage before minus with that of now over every point, relative
//    1e-12 (round-off of sums of about ten times the released energy:
//    measured up to 4.5e-14);
// 2. it equals the base class's evaluation of the changed points only
//    (Material::released_energy(), compute_stage() and compute_force() at
//    both states), relative 1e-12;
// 3. it writes nothing: the stage fields and the scratch arrays are as
//    before the call.
// Elastic plastic (whose energy is K theta^2/2 + alpha/2 s^2 n, the return
// factor s of the trial norm n) and Viscoelastic (quadratic in e^d through
// the step's back extension) likewise, also from a committed plastic or
// relaxing state (dt = tau / 4); Elastic correspondence uses the base
// class's: 1. only.
// Round-off values differ between rank counts: lines print PASS/FAILED only.

#include "harness.h"

using namespace pdtest;

namespace
{
  const Point<3>     lower(0, 0, 0), upper(1, 1, 1);
  const unsigned int n       = 8;
  const double       horizon = 3.015 / n;

  struct Variant : EnergyVariant
  {
    bool                                    continuous = false;
    std::function<double(const Point<3> &)> weight     = {};
    bool                                    own        = true; // the material overrides released_energy()
    bool                                    history    = false; // first a committed step to 2/3 of the displacement
  };
} // namespace

int
main(int argc, char *argv[])
{
  return run_checks(argc, argv, [](const MPI_Comm comm, Report &report) {
    const MaterialSpec pmb{"PMB", {{"Density", "1"}, {"Bulk modulus", "1"}, {"Thermal expansion coefficient", "0.01"}}};
    const MaterialSpec lps{"LPS",
                           {{"Density", "1"},
                            {"Bulk modulus", "1"},
                            {"Shear modulus", "0.35"},
                            {"Thermal expansion coefficient", "0.01"}}};
    std::vector<Variant> variants;
    const auto           add = [&variants](EnergyVariant base) -> Variant & {
      variants.push_back(Variant{std::move(base)});
      return variants.back();
    };
    for (const EnergyVariant &v : energy_variants(n))
      add(v);
    add({"PMB, continuous damage", pmb}).continuous                                  = true;
    add({"LPS, continuous damage, temperature", lps, false, false, true}).continuous = true;
    const auto weight = [](const Point<3> &x) { return 0.25 + 0.75 * x[0]; };
    add({"PMB, energy weight", pmb}).weight = weight;
    add({"LPS, energy weight", lps}).weight = weight;
    const std::map<std::string, std::string> moduli = {{"Density", "1"}, {"Bulk modulus", "1"}, {"Shear modulus", "0.35"}};
    add({"Elastic plastic", {"Elastic plastic", moduli}}).spec.keys["Yield stress"] = "1e-3";
    {
      Variant &v = add({"Elastic plastic, H = G, partial volumes, temperature, from a plastic state",
                        {"Elastic plastic", moduli}, true, false, true});
      v.spec.keys["Yield stress"]                  = "1e-3";
      v.spec.keys["Hardening modulus"]             = "0.35";
      v.spec.keys["Thermal expansion coefficient"] = "0.01";
      v.history                                    = true;
    }
    add({"Elastic plastic, periodic", {"Elastic plastic", moduli}, false, true}).spec.keys["Yield stress"] = "1e-3";
    {
      Variant &v                      = add({"Viscoelastic", {"Viscoelastic", moduli}});
      v.spec.keys["Relaxation time"]  = "1";
      v.spec.keys["Viscous fraction"] = "0.6";
    }
    {
      Variant &v = add({"Viscoelastic, partial volumes, temperature, from a relaxing state",
                        {"Viscoelastic", moduli}, true, false, true});
      v.spec.keys["Relaxation time"]               = "1";
      v.spec.keys["Viscous fraction"]              = "0.6";
      v.spec.keys["Thermal expansion coefficient"] = "0.01";
      v.history                                    = true;
    }
    add({"Elastic correspondence (base class)", {"Elastic correspondence", moduli}}).own = false;

    for (const Variant &v : variants)
      {
        report.line(v.name + ":");
        Harness h(comm, lower, upper, {{n, n, n}}, horizon, v.spec, v.weight, v.partial,
                  {{v.periodic, v.periodic, v.periodic}}, v.second);
        if (v.heated)
          {
            h.temperature_change.resize(h.cloud.n_local());
            for (unsigned int i = 0; i < h.cloud.n_local(); ++i)
              h.temperature_change[i] = 0.05 * noise(h.cloud.hash(i), 7);
          }
        h.dt = 0.25; // Viscoelastic: tau / 4
        if (v.history)
          {
            // Plastic extensions and strain of a first step (Elastic plastic: e^dp_N != 0).
            h.set_random_displacement(2e-3);
            h.evaluate(false);
            h.fields->commit();
          }
        h.set_random_displacement(3e-3);
        const unsigned int n_owned = h.cloud.n_owned();
        const auto        &bonds   = h.bonds;

        // The damage before and now, a function of the bond's two ends alone.
        std::vector<std::uint8_t> broken_before(bonds.n_bonds(), 0), broken_now(bonds.n_bonds(), 0);
        std::vector<double>       d_before, d_now;
        if (v.continuous)
          {
            d_before.assign(bonds.n_bonds(), 0.0);
            d_now.assign(bonds.n_bonds(), 0.0);
          }
        for (unsigned int i = 0; i < n_owned; ++i)
          for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
            {
              const std::uint64_t pair = h.cloud.hash(i) ^ h.cloud.hash(bonds.neighbor[b]);
              const double        a = 0.5 * (noise(pair, 11) + 1), c = 0.5 * (noise(pair, 12) + 1);
              if (v.continuous)
                {
                  d_before[b] = 0.3 * a;
                  d_now[b]    = d_before[b] + (c < 0.2 ? 2 * c : 0.0);
                }
              else
                {
                  broken_before[b] = a < 0.05;
                  broken_now[b]    = broken_before[b] || c < 0.1;
                }
            }
        const auto at = [&](const std::vector<std::uint8_t> &broken, const std::vector<double> &d) {
          perideal::ModelState s = h.state(true);
          s.broken               = broken.data();
          s.damage               = d.empty() ? nullptr : d.data();
          return s;
        };

        // 1. The reference: two whole evaluations.
        const auto whole = [&](const perideal::ModelState &s) {
          std::fill(h.force.begin(), h.force.begin() + 3 * n_owned, 0.0);
          std::fill(h.energy.begin(), h.energy.end(), 0.0);
          for (unsigned int b = 0; b < h.materials.size(); ++b)
            h.materials[b]->compute_stage(s, h.block_points[b]);
          h.fields->update_ghost_values(perideal::FieldUse::stage);
          for (unsigned int b = 0; b < h.materials.size(); ++b)
            h.materials[b]->compute_force(s, h.block_points[b]);
          double e = 0;
          for (unsigned int i = 0; i < n_owned; ++i)
            e += h.cloud.volume[i] * h.energy[i];
          return Utilities::MPI::sum(e, comm);
        };
        const perideal::ModelState before = at(broken_before, d_before), now = at(broken_now, d_now);
        const double               reference_before = whole(before);
        const double               reference        = reference_before - whole(now);

        // The changed points by block, as ForceModel::released_energy() finds them.
        std::vector<std::vector<unsigned int>> changed(h.materials.size());
        for (unsigned int i = 0; i < n_owned; ++i)
          for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
            if (broken_before[b] != broken_now[b] || (v.continuous && d_before[b] != d_now[b]))
              {
                changed[h.cloud.block[i]].push_back(i);
                break;
              }
        // Scratch arrays marked, to see that the material's own pass writes none.
        std::vector<double> scratch_force(3 * n_owned, 7.0), scratch_energy(n_owned, 7.0);
        perideal::ModelState s_before = before, s_now = now;
        s_before.force = s_now.force = scratch_force.data();
        s_before.energy = s_now.energy = scratch_energy.data();
        // The stage field the material's own pass must leave alone.
        const std::string   stage_field = v.spec.model == "LPS" ? "dilatation" :
                                          v.spec.model == "Elastic plastic" ? "eps_scale" :
                                          v.spec.model == "Viscoelastic"    ? "ves_dilatation" : "";
        std::vector<double> stage;
        if (!stage_field.empty())
          stage.assign(h.fields->get(stage_field).begin(), h.fields->get(stage_field).begin() + n_owned);
        double own = 0;
        for (unsigned int b = 0; b < h.materials.size(); ++b)
          own += h.materials[b]->released_energy(s_before, s_now, changed[b]);
        own = Utilities::MPI::sum(own, comm);
        report.check("  released energy / sum V W before", own / reference_before, std::abs(own) > 0.005 * reference_before,
                     "|.| > 0.005: a change worth checking (Elastic correspondence: breaks can raise W)");
        report.below("  |released_energy() - two whole evaluations| / released", std::abs(own - reference) / reference, 1e-12);
        if (!v.own)
          continue;

        // 3. Nothing written.
        bool untouched = std::all_of(scratch_force.begin(), scratch_force.end(), [](double x) { return x == 7.0; }) &&
                         std::all_of(scratch_energy.begin(), scratch_energy.end(), [](double x) { return x == 7.0; });
        if (!stage_field.empty())
          for (unsigned int i = 0; i < n_owned; ++i)
            untouched = untouched && h.fields->get(stage_field).local_element(i) == stage[i];
        untouched = Utilities::MPI::min(untouched ? 1 : 0, comm) == 1;
        report.check("  scratch arrays and stage fields untouched", untouched ? 1 : 0, untouched, "== 1");

        // 2. The base class's evaluation of the changed points.
        double base = 0;
        for (unsigned int b = 0; b < h.materials.size(); ++b)
          base += h.materials[b]->perideal::Material::released_energy(s_before, s_now, changed[b]);
        base = Utilities::MPI::sum(base, comm);
        report.below("  |released_energy() - Material::released_energy()| / released", std::abs(own - base) / base, 1e-12);
      }
  });
}
