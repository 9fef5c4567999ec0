// Viscoelastic (Mitchell) in uniaxial strain: relaxation and creep against
// the standard linear solid.
//
// The bar of elastic_plastic_uniaxial.cc (1.2 x 0.25 x 0.25, 24 x 5 x 5
// points, periodic in y and z, horizon 2.015 h), K = 1, G = 0.35, tau_b = 2,
// lambda_i = 0.6; every point moves with u = (eps x, 0, 0) and sigma_xx is
// the force across x = 0.6 over the cross-section (interior state only).
// With the lattice's sums m and Q (see elastic_plastic_uniaxial.cc) the
// model's small-strain stress is sigma = K eps + M (lambda_inf eps +
// lambda_i (eps - eps_b)), M = 15 G Q / m: a standard linear solid with the
// relaxation modulus E(t) = E_inf + E_1 exp(-t/tau_b), E_inf = K + M
// lambda_inf, E_1 = M lambda_i.
// 1. Relaxation: eps = 1e-6 applied at t = 0 (dt = 0) and held for 30 steps
//    of tau_b / 10: sigma(t) / (eps E(t)) - 1 below 1e-5 at every step (the
//    update is exact for a held extension; the strain's geometric
//    nonlinearity is ~1e-6). Energy: the stored energy's drop equals the dissipation
//    (integrated exactly over each step, as e^b is updated): |drop - D| /
//    drop < 1e-10 (measured 4.9e-15; the trapezoid rule of before gave
//    3.3e-3; without the dissipation the gap is 100%).
// 2. Creep: sigma0 = 1e-6 E(0) applied at t = 0 and held; each step (30 of
//    tau_b / 10) solves sigma(eps) = sigma0 for the bar's strain (sigma is
//    affine in eps for a given history up to the geometric nonlinearity:
//    one secant step, checked to 1e-7).
//    Against the SLS creep eps(t) = sigma0 [1/E_inf - (1/E_inf - 1/E_0)
//    exp(-t/tau_c)], tau_c = tau_b E_0 / E_inf: max relative error < 2e-3
//    (the step's linear-in-time extension is second order; measured below
//    1e-3), and the first step's strain = sigma0 / E_0 within 1e-5.

#include "harness.h"

using namespace pdtest;

namespace
{
  constexpr double K = 1, G = 0.35, tau = 2, lambda_i = 0.6;

  struct Bar
  {
    Harness hs;
    double  M;

    explicit Bar(const MPI_Comm comm)
      : hs(comm, Point<3>(0, 0, 0), Point<3>(1.2, 0.25, 0.25), {{24, 5, 5}}, 2.015 * 0.05,
           {"Viscoelastic",
            {{"Density", "1"},
             {"Bulk modulus", "1"},
             {"Shear modulus", "0.35"},
             {"Relaxation time", "2"},
             {"Viscous fraction", "0.6"}}},
           {}, false, {{false, true, true}})
    {
      const double  h = 0.05, V = h * h * h;
      const Lattice L = complete_family(h, 2.015 * h, V);
      double        Q = 0;
      for (const auto &xi : L.xi)
        {
          const double nx2 = xi[0] * xi[0] / xi.norm_square();
          Q += xi.norm_square() * (nx2 - 1.0 / 3) * (nx2 - 1.0 / 3) * V;
        }
      M = 15 * G * Q / L.m;
    }

    /// sigma_xx across x = 0.6 under u = (eps x, 0, 0) at the harness's time
    /// step, and the stored and dissipated energies of the whole bar.
    double
    stress(const double eps, double *stored = nullptr, double *dissipated = nullptr)
    {
      hs.set_displacement([&](const Point<3> &x) {
        Tensor<1, 3> d;
        d[0] = eps * x[0];
        return d;
      });
      hs.evaluate();
      double cut = 0, W = 0, D = 0;
      for (unsigned int i = 0; i < hs.cloud.n_owned(); ++i)
        {
          if (hs.cloud.position(i)[0] > 0.6)
            cut += hs.cloud.volume[i] * hs.force.local_element(3 * i);
          W += hs.cloud.volume[i] * hs.energy[i];
          D += hs.cloud.volume[i] * hs.field("ves_dissipation", i);
        }
      if (stored)
        *stored = Utilities::MPI::sum(W, hs.comm);
      if (dissipated)
        *dissipated = Utilities::MPI::sum(D, hs.comm);
      return -Utilities::MPI::sum(cut, hs.comm) / (0.25 * 0.25);
    }
  };

  void
  relaxation(const MPI_Comm comm, Report &report)
  {
    Bar          bar(comm);
    const double E_inf = K + bar.M * (1 - lambda_i), E_1 = bar.M * lambda_i, eps = 1e-6, dt = tau / 10;
    report.line("relaxation: M / (4G/3) = " + sci(bar.M / (4 * G / 3), 6) + " (the lattice's)");
    double W0 = 0, D = 0, W = 0, worst = 0;
    bar.stress(eps, &W0);
    bar.hs.fields->commit();
    bar.hs.dt = dt;
    for (unsigned int k = 1; k <= 30; ++k)
      {
        bar.hs.time        = k * dt;
        const double sigma = bar.stress(eps, &W, &D);
        bar.hs.fields->commit();
        worst = std::max(worst, std::abs(sigma / (eps * (E_inf + E_1 * std::exp(-double(k) * dt / tau))) - 1));
      }
    report.check("  max |sigma(t) / (eps E(t)) - 1| over 3 tau_b", worst, worst < 1e-5, "< 1e-5");
    report.value("  stored energy at t = 0", W0);
    report.value("  stored energy at t = 3 tau_b", W);
    report.value("  viscous dissipation", D);
    const double gap = std::abs(W0 - W - D) / (W0 - W);
    report.below("  |stored energy drop - dissipation| / drop", gap, 1e-10);
  }

  void
  creep(const MPI_Comm comm, Report &report)
  {
    Bar          bar(comm);
    const double E_inf = K + bar.M * (1 - lambda_i), E_0 = K + bar.M, dt = tau / 10;
    const double sigma0 = 1e-6 * E_0, tau_c = tau * E_0 / E_inf;
    double       eps = sigma0 / E_0, worst = 0, residual = 0;
    for (unsigned int k = 0; k <= 30; ++k)
      {
        bar.hs.dt   = k == 0 ? 0.0 : dt;
        bar.hs.time = k * dt;
        // sigma is affine in eps here: a secant from two strains solves it.
        const double s1 = bar.stress(eps), eps2 = eps * (1 + 1e-2), s2 = bar.stress(eps2);
        eps             = eps + (sigma0 - s1) * (eps2 - eps) / (s2 - s1);
        residual        = std::max(residual, std::abs(bar.stress(eps) / sigma0 - 1));
        bar.hs.fields->commit();
        const double expected = sigma0 * (1 / E_inf - (1 / E_inf - 1 / E_0) * std::exp(-double(k) * dt / tau_c));
        if (k == 0)
          report.check("  creep: eps(0+) E_0 / sigma0 - 1", eps / expected - 1, std::abs(eps / expected - 1) < 1e-5,
                       "|.| < 1e-5");
        worst = std::max(worst, std::abs(eps / expected - 1));
      }
    report.check("  held stress: max |sigma / sigma0 - 1|", residual, residual < 1e-7, "< 1e-7");
    report.value("  creep strain at 3 tau_b over sigma0 / E_0", eps * E_0 / sigma0);
    report.check("  max |eps(t) / eps_SLS(t) - 1| over 3 tau_b", worst, worst < 2e-3, "< 2e-3");
  }
} // namespace

int
main(int argc, char *argv[])
{
  return run_checks(argc, argv, [](const MPI_Comm comm, Report &report) {
    relaxation(comm, report);
    creep(comm, report);
  });
}
