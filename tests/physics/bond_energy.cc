// The bond energy w of Material::bond_energies(), what the Critical energy
// damage model compares with w_c = 4 G_c / (pi delta^4) (doc/models.md).
//
// Unit cube, 8^3 points, horizon 3.015 h, a random displacement of amplitude
// 1e-3 (the same on any number of ranks). For every variant of the
// materials that give a bond energy (PMB, LPS with omega = 1 and 1 - r, the
// surface corrections, partial volumes, a periodic box, a temperature field,
// two blocks of different horizons), checked:
// 1. the bond energies share the strain energy exactly: sum over the
//    directed bonds of w beta V_i V_j / 2 (beta the partial volume
//    fraction, 1 without) equals sum_i V_i W_i, relative 1e-12: w is each
//    bond's part of the material's own energy, not a second model of it;
// 2. both halves of a bond get the same w bit for bit (pairs with both
//    ends owned here), so both owners decide alike;
// 3. PMB: w = c s^2 |xi| / 2 with c = 18 K / (pi delta^4), within 1e-13 of
//    the largest w (the library's arithmetic may fuse multiply-adds, which
//    moves the stretch of a nearly unstretched bond by more than 1e-13 of
//    itself).
// Round-off values differ between rank counts: lines print PASS/FAILED only.

#include "harness.h"

using namespace pdtest;

namespace
{
  const Point<3>     lower(0, 0, 0), upper(1, 1, 1);
  const unsigned int n       = 8;
  const double       horizon = 3.015 / n;

  struct Variant
  {
    std::string  name;
    MaterialSpec spec;
    bool         partial  = false;
    bool         periodic = false;
    bool         heated   = false;
    SecondBlock  second   = {};
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
    std::vector<Variant> variants = {{"PMB", pmb}, {"LPS, omega = 1", lps}};
    variants.push_back({"LPS, omega = 1 - r", lps});
    variants.back().spec.keys["Influence function"] = "1 - r";
    variants.push_back({"PMB, surface correction", pmb});
    variants.back().spec.keys["Surface correction"] = "Energy";
    variants.push_back({"LPS, surface correction", lps});
    variants.back().spec.keys["Surface correction"] = "Energy";
    variants.push_back({"PMB, partial volumes", pmb, true});
    variants.push_back({"LPS, partial volumes", lps, true});
    variants.push_back({"PMB, periodic", pmb, false, true});
    variants.push_back({"LPS, periodic", lps, false, true});
    variants.push_back({"PMB, temperature", pmb, false, false, true});
    variants.push_back({"LPS, temperature", lps, false, false, true});
    variants.push_back({"PMB, two horizons", pmb, false, false, false, {0.5, 2.015 / n}});
    variants.push_back({"LPS, two horizons", lps, false, false, false, {0.5, 2.015 / n}});

    for (const Variant &v : variants)
      {
        report.line(v.name + ":");
        Harness h(comm, lower, upper, {{n, n, n}}, horizon, v.spec, {}, v.partial,
                  {{v.periodic, v.periodic, v.periodic}}, v.second);
        if (v.heated)
          {
            h.temperature_change.resize(h.cloud.n_local());
            for (unsigned int i = 0; i < h.cloud.n_local(); ++i)
              h.temperature_change[i] = 0.05 * noise(h.cloud.hash(i), 7);
          }
        h.set_random_displacement(1e-3);
        h.evaluate(true);
        const perideal::ModelState state = h.state(false);
        const unsigned int         n_owned = h.cloud.n_owned();
        const auto                &bonds   = h.bonds;
        std::vector<double>        w(bonds.n_bonds());
        for (unsigned int i = 0; i < n_owned; ++i)
          h.materials[h.cloud.block[i]]->bond_energies(state, i, w.data() + bonds.offsets[i]);

        double sums[2] = {0, 0}; // sum of the bonds' shares, sum of V W
        double pmb_error = 0, pmb_scale = 0, asymmetry = 0;
        for (unsigned int i = 0; i < n_owned; ++i)
          {
            const double Vi = h.cloud.volume[i];
            sums[1] += Vi * h.energy[i];
            for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
              {
                const unsigned int j    = bonds.neighbor[b];
                const double       beta = bonds.volume_fraction.empty() ? 1.0 : bonds.volume_fraction[b];
                sums[0] += 0.5 * w[b] * beta * Vi * h.cloud.volume[j];
                if (j < n_owned)
                  for (std::size_t c = bonds.offsets[j]; c < bonds.offsets[j + 1]; ++c)
                    if (bonds.neighbor[c] == i)
                      asymmetry = std::max(asymmetry, std::abs(w[c] - w[b]));
                if (v.spec.model == "PMB" && v.spec.keys.count("Surface correction") == 0 && v.second.horizon == 0)
                  {
                    // The kernels' kinematics (bond_vectors), so that both see the same round-off.
                    const perideal::BondOrigin origin(h.cloud.X.data(), h.u.begin(), i);
                    double                     xi[3], y[3];
                    if (v.periodic)
                      perideal::bond_vectors<true>(h.cloud.X.data(), h.u.begin(), j, origin, h.cloud.periodicity, xi, y);
                    else
                      perideal::bond_vectors<false>(h.cloud.X.data(), h.u.begin(), j, origin, h.cloud.periodicity, xi, y);
                    const double r0 = std::sqrt(xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]);
                    const double r  = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
                    const double s  = (r - r0) / r0 -
                                     (v.heated ? 0.005 * (h.temperature_change[i] + h.temperature_change[j]) : 0.0);
                    const double c = 18 / (M_PI * std::pow(horizon, 4));
                    const double expected = 0.5 * c * s * s * r0;
                    pmb_error = std::max(pmb_error, std::abs(w[b] - expected));
                    pmb_scale = std::max(pmb_scale, expected);
                  }
              }
          }
        Utilities::MPI::sum(ArrayView<const double>(sums, 2), comm, ArrayView<double>(sums, 2));
        report.below("  |sum w beta V_i V_j / 2 - sum V W| / sum V W", std::abs(sums[0] - sums[1]) / sums[1], 1e-12);
        asymmetry = Utilities::MPI::max(asymmetry, comm);
        report.check("  max |w_ij - w_ji| (both ends owned here)", asymmetry, asymmetry == 0, "== 0");
        if (v.spec.model == "PMB" && v.spec.keys.count("Surface correction") == 0 && v.second.horizon == 0)
          report.below("  max |w - c s^2 |xi| / 2| / max w",
                       Utilities::MPI::max(pmb_error, comm) / Utilities::MPI::max(pmb_scale, comm), 1e-13);
      }
  });
}
