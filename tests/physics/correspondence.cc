// Elastic correspondence (source/material/elastic_correspondence.cc), K = 2.5,
// G = 1.1 (lambda = 1.7667), rho = 1.3, both strain measures. Checked:
//
// 1. Affine map y = F X, F not symmetric and not small (|F - I| ~ 0.4): the
//    computed F_i equals F at every point, surface points included, within
//    1e-12 (F_i = (sum Y (x) xi V) K^-1 with Y = F xi exactly: round-off of a
//    sum of ~100 terms, ~1e-15).
// 2. A rigid rotation by 90 deg about an off-axis line: the Cauchy stress is
//    zero at every point, max |sigma| / K below 1e-12 (F = Q to round-off
//    ~1e-15; the stress is linear in F^T F - I or U - I).
// 3. Uniaxial strain u = (e X, 0, 0), e = 0.01, at every point (F exact):
//    Green-Lagrange: E_xx = e + e^2/2, S = lambda tr E I + 2 G E,
//    sigma = F S F^T / J: sigma_xx = (1+e) (lambda + 2G) E_xx, sigma_yy =
//    lambda E_xx / (1+e); small strain (U = F): sigma_xx = (lambda + 2G) e,
//    sigma_yy = lambda e. Relative error below 1e-10.
// 4. A checkerboard u = a s(i) n, s = +-1 alternating over the lattice, n =
//    (1, 2, 3)/|.|, a = 1e-3 h, cube 16^3: in the interior F = I exactly
//    (every bond has a mirror with the same displacement difference), so
//    without stabilization the points deeper than 2 horizons (whose
//    neighbors' families are complete too) feel nothing but round-off: max
//    |f| below 1e-9 K a / horizon^2 (round-off of y = X + u, ~1e-16 against
//    a = 6e-5, over ~100 bonds). With Hourglass and with Silling (coefficient
//    0.02, the defaults) the force there must exceed 10x that of None. The
//    maximum over all points is printed (near the surface the unstabilized
//    model feels the mode through its one-sided families).
// 5. f = -dE/du: the directional derivative of E = sum V W along a random
//    v (central differences, step 1e-6, at a random state of 1e-4, strains
//    ~1e-3) equals -sum V f.v, for None and Silling (potential forces):
//    within 1e-6 (relative) with Green-Lagrange (P = dW/dF exactly); within
//    1e-2 with Small strain, whose P = J sigma F^-T is the derivative of
//    W(U) to first order in the strain only (relative difference O(|eps|)).
// 6. Damage: all bonds of one point broken (continuous d = 1): its force is
//    exactly 0 and finite elsewhere; a cut (binary broken flags on every bond
//    crossing x = 0.7) under a uniform stretch 1e-3 makes the points beside
//    the cut feel a free surface: their force changes by more than
//    K 1e-3 / horizon (the scale of a surface's unbalanced traction).
// 7. Thermal strain: F = (1 + alpha dT) I with a uniform dT gives no stress
//    and no force at any point (below 1e-12 K and 1e-10 f_ref).

#include "harness.h"

using namespace pdtest;

namespace
{
  MaterialSpec
  spec(const std::string &strain, const std::string &stabilization, const std::string &alpha = "0")
  {
    return {"Elastic correspondence",
            {{"Density", "1.3"},
             {"Bulk modulus", "2.5"},
             {"Shear modulus", "1.1"},
             {"Strain measure", strain},
             {"Stabilization", stabilization},
             {"Thermal expansion coefficient", alpha}}};
  }

  Tensor<2, 3>
  tensor_field(Harness &h, const std::string &name, const unsigned int i)
  {
    Tensor<2, 3> T;
    for (unsigned int p = 0; p < 3; ++p)
      for (unsigned int q = 0; q < 3; ++q)
        T[p][q] = h.fields->get(name).local_element(9 * i + 3 * p + q);
    return T;
  }

  /// compute_stage, ghosts, compute_force with a state the caller adjusted.
  void
  evaluate(Harness &h, const perideal::ModelState &s)
  {
    std::fill(h.force.begin(), h.force.begin() + 3 * h.cloud.n_owned(), 0.0);
    if (s.energy)
      std::fill(h.energy.begin(), h.energy.end(), 0.0);
    h.material->compute_stage(s, h.points);
    h.fields->update_ghost_values(perideal::FieldUse::stage);
    h.material->compute_force(s, h.points);
  }

  double
  max_force(Harness &h, const std::function<bool(unsigned int)> &where = {})
  {
    double m = 0;
    for (unsigned int i = 0; i < h.cloud.n_owned(); ++i)
      if (!where || where(i))
        m = std::max(m, h.force_of(i).norm());
    return Utilities::MPI::max(m, h.comm);
  }
} // namespace

int
main(int argc, char *argv[])
{
  return run_checks(argc, argv, [](const MPI_Comm comm, Report &report) {
    const double K = 2.5, G = 1.1, lambda = K - 2 * G / 3;
    const double f_ref = K * 1e-3 / rigid_box::horizon;
    for (const std::string strain : {"Green-Lagrange", "Small strain"})
      {
        report.line("Strain measure = " + strain);
        Harness h(comm, rigid_box::lower, rigid_box::upper, rigid_box::cells, rigid_box::horizon,
                  spec(strain, "Hourglass"));
        const unsigned int n = h.cloud.n_owned();

        // 1. Affine map.
        Tensor<2, 3>       F;
        const double       entries[3][3] = {{1.2, 0.3, -0.1}, {0.05, 0.9, 0.25}, {-0.2, 0.1, 1.1}};
        for (unsigned int a = 0; a < 3; ++a)
          for (unsigned int b = 0; b < 3; ++b)
            F[a][b] = entries[a][b];
        h.set_displacement([&](const Point<3> &x) { return Tensor<1, 3>(F * x - x); });
        h.evaluate(true);
        double dF = 0;
        for (unsigned int i = 0; i < n; ++i)
          dF = std::max(dF, (tensor_field(h, "corr_F", i) - F).norm());
        report.below("  1. affine map, every point: max |F_i - F|", Utilities::MPI::max(dF, comm), 1e-12);

        // 2. Rigid rotation by 90 degrees.
        const Tensor<2, 3> Q = rotation(rigid_box::axis, M_PI / 2);
        Tensor<1, 3>       p;
        p[0] = 0.9, p[1] = 0.5, p[2] = -0.2;
        h.set_displacement([&](const Point<3> &x) { return Tensor<1, 3>(Q * (x - p) + p - x); });
        h.evaluate(true);
        double s_max = 0;
        for (unsigned int i = 0; i < n; ++i)
          s_max = std::max(s_max, tensor_field(h, "corr_cauchy", i).norm());
        report.below("  2. rotation 90 deg, every point: max |sigma| / K", Utilities::MPI::max(s_max, comm) / K, 1e-12);
        report.below("     max |f| / (K 1e-3 / horizon)", max_force(h) / f_ref, 1e-10);

        // 3. Uniaxial strain.
        const double e = 0.01;
        h.set_displacement([&](const Point<3> &x) {
          Tensor<1, 3> u;
          u[0] = e * x[0];
          return u;
        });
        h.evaluate(true);
        double sxx, syy;
        if (strain == "Green-Lagrange")
          {
            const double Exx = e + e * e / 2;
            sxx = (1 + e) * (lambda + 2 * G) * Exx;
            syy = lambda * Exx / (1 + e);
          }
        else
          sxx = (lambda + 2 * G) * e, syy = lambda * e;
        Tensor<2, 3> expected;
        expected[0][0] = sxx, expected[1][1] = syy, expected[2][2] = syy;
        double ds = 0;
        for (unsigned int i = 0; i < n; ++i)
          ds = std::max(ds, (tensor_field(h, "corr_cauchy", i) - expected).norm() / expected.norm());
        report.below("  3. uniaxial strain 0.01, every point: max |sigma - sigma_exact| / |sigma_exact|",
                     Utilities::MPI::max(ds, comm), 1e-10);
        report.value("     sigma_xx", sxx);

        // 5. f = -dE/du along a random direction, potential variants.
        for (const std::string stab : {"None", "Silling"})
          {
            Harness g(comm, rigid_box::lower, rigid_box::upper, rigid_box::cells, rigid_box::horizon, spec(strain, stab));
            std::vector<double> u0(3 * n), v(3 * n);
            for (unsigned int i = 0; i < n; ++i)
              for (unsigned int c = 0; c < 3; ++c)
                {
                  u0[3 * i + c] = 1e-4 * noise(g.cloud.hash(i), c);
                  v[3 * i + c]  = noise(g.cloud.hash(i), 7 + c);
                }
            const auto energy = [&](const double t) {
              std::vector<double> w(3 * n);
              for (unsigned int k = 0; k < 3 * n; ++k)
                w[k] = u0[k] + t * v[k];
              g.set_displacement(w);
              g.evaluate(true);
              double E = 0;
              for (unsigned int i = 0; i < n; ++i)
                E += g.cloud.volume[i] * g.energy[i];
              return Utilities::MPI::sum(E, comm);
            };
            const double eps = 1e-6;
            const double dE  = (energy(eps) - energy(-eps)) / (2 * eps);
            energy(0);
            double fv = 0;
            for (unsigned int k = 0; k < 3 * n; ++k)
              fv += g.cloud.volume[k / 3] * g.force.local_element(k) * v[k];
            fv = Utilities::MPI::sum(fv, comm);
            report.below("  5. Stabilization = " + stab + ": |dE/dt + sum V f.v| / |sum V f.v|", std::abs(dE + fv) / std::abs(fv),
                         strain == "Green-Lagrange" ? 1e-6 : 1e-2);
          }
      }

    // 4. Checkerboard.
    {
      const unsigned int cells = 16;
      const double       hh = 1.0 / cells, horizon = 3.015 * hh, a = 1e-3 * hh, scale = K * a / (horizon * horizon);
      const Point<3>     lo(0, 0, 0), hi(1, 1, 1);
      Tensor<1, 3>       dir;
      dir[0] = 1, dir[1] = 2, dir[2] = 3;
      dir /= dir.norm();
      std::map<std::string, double> f_all, f_deep;
      for (const std::string stab : {"None", "Hourglass", "Silling"})
        {
          Harness h(comm, lo, hi, {{cells, cells, cells}}, horizon, spec("Green-Lagrange", stab));
          h.set_displacement([&](const Point<3> &x) {
            const int s = int(std::floor(x[0] / hh)) + int(std::floor(x[1] / hh)) + int(std::floor(x[2] / hh));
            return Tensor<1, 3>((s % 2 ? a : -a) * dir);
          });
          h.evaluate(false);
          f_all[stab]  = max_force(h) / scale;
          f_deep[stab] = max_force(h, [&](unsigned int i) { return h.depth(i, lo, hi) > 2 * horizon; }) / scale;
          report.value("  4. checkerboard a = 1e-3 h, Stabilization = " + stab +
                         ": max |f| / (K a / horizon^2), every point",
                       f_all[stab]);
          if (stab != "None")
            report.value("     deeper than 2 horizons", f_deep[stab]);
        }
      report.below("  4. None, deeper than 2 horizons (F = I there): max |f| / (K a / horizon^2)", f_deep["None"],
                   1e-9);
      for (const std::string stab : {"Hourglass", "Silling"})
        report.above("  4. " + stab + " / None, deeper than 2 horizons (None's force is round-off)",
                     f_deep[stab] / f_deep["None"], 10);
    }

    // 6. Damage.
    {
      Harness            h(comm, rigid_box::lower, rigid_box::upper, rigid_box::cells, rigid_box::horizon,
                spec("Green-Lagrange", "Silling"));
      const unsigned int n = h.cloud.n_owned();
      h.set_displacement(non_affine_displacement);
      // The point nearest the box's centre loses every bond, both halves.
      const Point<3> centre(0.7, 0.3, 0.6); // of rigid_box
      double         best   = 1e300;
      for (unsigned int i = 0; i < h.cloud.n_local(); ++i)
        best = std::min(best, h.cloud.position(i).distance(centre));
      best = Utilities::MPI::min(best, comm);
      const auto isolated = [&](const unsigned int i) { return h.cloud.position(i).distance(centre) == best; };
      h.damage.assign(h.bonds.n_bonds(), 0.0);
      for (unsigned int i = 0; i < n; ++i)
        for (std::size_t b = h.bonds.offsets[i]; b < h.bonds.offsets[i + 1]; ++b)
          if (isolated(i) || isolated(h.bonds.neighbor[b]))
            h.damage[b] = 1;
      h.evaluate(true);
      double f_isolated = 0, f_other = 0;
      bool   finite = true;
      for (unsigned int i = 0; i < n; ++i)
        {
          const double fi = h.force_of(i).norm();
          finite &= std::isfinite(fi);
          if (isolated(i))
            f_isolated = std::max(f_isolated, fi);
          else
            f_other = std::max(f_other, fi);
        }
      report.check("  6. all bonds of one point broken: its |f|", Utilities::MPI::max(f_isolated, comm),
                   Utilities::MPI::max(f_isolated, comm) == 0, "exactly 0");
      report.check("     every other point's force finite", Utilities::MPI::min(double(finite), comm), Utilities::MPI::min(double(finite), comm) == 1, "1");
      report.value("     max |f| of the others / (K 1e-3 / horizon)", Utilities::MPI::max(f_other, comm) / f_ref);
      h.damage.clear();

      // A cut at x = 0.7 (binary flags, the critical-stretch path), uniform stretch.
      const double cut = 0.7;
      h.set_displacement([&](const Point<3> &x) { return Tensor<1, 3>(1e-3 * x); });
      std::vector<std::uint8_t> broken(h.bonds.n_bonds(), 0);
      for (unsigned int i = 0; i < n; ++i)
        for (std::size_t b = h.bonds.offsets[i]; b < h.bonds.offsets[i + 1]; ++b)
          broken[b] = (h.cloud.position(i)[0] - cut) * (h.cloud.position(h.bonds.neighbor[b])[0] - cut) < 0;
      const auto beside = [&](const unsigned int i) { return std::abs(h.cloud.position(i)[0] - cut) < 0.1; };
      perideal::ModelState s = h.state(true);
      std::vector<std::uint8_t> none(h.bonds.n_bonds(), 0);
      s.broken = none.data();
      evaluate(h, s);
      std::vector<Tensor<1, 3>> f_uncut(n);
      for (unsigned int i = 0; i < n; ++i)
        f_uncut[i] = h.force_of(i);
      s.broken = broken.data();
      evaluate(h, s);
      double df = 0;
      for (unsigned int i = 0; i < n; ++i)
        if (beside(i))
          df = std::max(df, (h.force_of(i) - f_uncut[i]).norm());
      df = Utilities::MPI::max(df, comm) / f_ref;
      report.check("  6. cut at x = 0.7, uniform stretch 1e-3: max |f_cut - f_uncut| beside it / (K 1e-3 / horizon)",
                   df, df > 1, "> 1: the cut acts as a free surface");
    }

    // 7. Thermal strain.
    {
      const double alpha = 2e-3, dT_value = 5;
      Harness      h(comm, rigid_box::lower, rigid_box::upper, rigid_box::cells, rigid_box::horizon,
                spec("Green-Lagrange", "Hourglass", "0.002"));
      std::vector<double> eps_T(h.cloud.n_local(), alpha * dT_value);
      h.set_displacement([&](const Point<3> &x) { return Tensor<1, 3>(alpha * dT_value * x); });
      perideal::ModelState s = h.state(true);
      s.thermal_strain       = eps_T.data();
      evaluate(h, s);
      double s_max = 0;
      for (unsigned int i = 0; i < h.cloud.n_owned(); ++i)
        s_max = std::max(s_max, tensor_field(h, "corr_cauchy", i).norm());
      report.below("  7. free heated body F = (1 + alpha dT) I: max |sigma| / K", Utilities::MPI::max(s_max, comm) / K, 1e-12);
      report.below("     max |f| / (K 1e-3 / horizon)", max_force(h) / f_ref, 1e-10);
      s.thermal_strain = nullptr;
      evaluate(h, s);
      report.value("     the same without the temperature: sigma_xx / K",
                   Utilities::MPI::max(tensor_field(h, "corr_cauchy", 0)[0][0], comm) / K);
    }
  });
}
