// Elastic plastic (Mitchell) in uniaxial strain, load beyond yield and unload.
//
// Bar [0, 1.2] x [0, 0.25]^2, 24 x 5 x 5 points (h = 0.05), periodic in y
// and z (no lateral surface), horizon 2.015 h; K = 1, G = 0.35, Y0 = 1e-3,
// H = 0 (perfectly plastic) and H = G (linear hardening). Every point moves
// with u = (eps x, 0, 0); eps rises to 4 eps_y in 16 equal steps, then falls
// by eps_y in 4 (elastic unloading, away from reverse yield at 2 eps_y); the
// history is committed after each step. The stress sigma_xx is the force the
// half x > 0.6 feels from the other half over the cross-section, -sum V f_x /
// A: only points with complete families act across the cut, so it is the
// homogeneous interior state's.
//
// Closed form of the discrete model (small strain): the family's sums m =
// sum |xi|^2 V and Q = sum |xi|^2 (n_x^2 - 1/3)^2 V (n = xi/|xi|, computed
// here from the lattice) make every deviatoric extension proportional to
// |xi| (n_x^2 - 1/3): the model is then J2 plasticity of one variable,
//   q = c1 (eps - eps'_p),  c1 = 15 G sqrt(Q / (5 m)),  sigma_xx = K eps + sqrt(5 Q / m) q,
// yield at q = Y0 + H eps_p, plastic increments eps_p += c1 d eps / (3G + H)
// (so dq = c1 H / (3G + H) d eps). The continuum values, c1 = 2G and
// sqrt(5Q/m) = 2/3, are printed for comparison: the cubic lattice at 2.015 h
// differs from them by a few percent (no surface here: its anisotropy).
// Checked, for both H:
// 1. sigma_xx at every step against the discrete closed form, relative to
//    the largest stress: < 1e-2 (the closed form is small-strain; the
//    geometric nonlinearity is O(eps), |eps| < 6e-3; measured 2.6e-3). A wrong yield constant (psi0 a factor 2 off) or
//    a wrong return (3G, H) is tens of percent off.
// 2. The unloading slope d sigma / d eps over the 4 unloading steps against
//    K + sqrt(5Q/m) c1 (elastic): < 1e-2 (geometric nonlinearity as in 1;
//    measured 3.5e-3).
// 3. Equivalent plastic strain at the interior points (0.3 < x < 0.9, every
//    one the same) against the closed form: < 2e-3 relative (measured 3e-4).
// 4. Energy: the work of the internal forces over the path (trapezoid rule
//    per step, sum over all points, the surfaces at the bar's ends
//    included) = stored energy sum V W + plastic dissipation sum V D at the
//    end, relative to the work: < 1e-2 (the trapezoid rule's error at the
//    yield kink; measured 7e-5). Without the dissipation the gap is ~27%.

#include "harness.h"

using namespace pdtest;

namespace
{
  constexpr double K = 1, G = 0.35, Y0 = 1e-3;

  void
  run(const MPI_Comm comm, Report &report, const double H)
  {
    const Point<3> lower(0, 0, 0), upper(1.2, 0.25, 0.25);
    const double   h = 0.05, horizon = 2.015 * h, A = 0.25 * 0.25, V = h * h * h;
    std::ostringstream Hs;
    Hs << std::setprecision(17) << H;
    Harness hs(comm, lower, upper, {{24, 5, 5}}, horizon,
               {"Elastic plastic",
                {{"Density", "1"},
                 {"Bulk modulus", "1"},
                 {"Shear modulus", "0.35"},
                 {"Yield stress", "0.001"},
                 {"Hardening modulus", Hs.str()}}},
               {}, false, {{false, true, true}});

    const Lattice L = complete_family(h, horizon, V);
    double        Q = 0;
    for (const auto &xi : L.xi)
      {
        const double nx2 = xi[0] * xi[0] / xi.norm_square();
        Q += xi.norm_square() * (nx2 - 1.0 / 3) * (nx2 - 1.0 / 3) * V;
      }
    const double c1 = 15 * G * std::sqrt(Q / (5 * L.m)), c2 = std::sqrt(5 * Q / L.m);
    report.line("Hardening modulus H = " + sci(H, 6) + ": lattice c1 / 2G = " + sci(c1 / (2 * G), 6) +
                ", sqrt(5Q/m) / (2/3) = " + sci(c2 / (2.0 / 3), 6));

    const double        eps_y = Y0 / c1;
    std::vector<double> path;
    for (unsigned int k = 1; k <= 16; ++k)
      path.push_back(4 * eps_y * k / 16);
    for (unsigned int k = 1; k <= 4; ++k)
      path.push_back(4 * eps_y - eps_y * k / 4);

    // The discrete closed form along the path.
    double q = 0, ep = 0, eps_old = 0;
    double max_error = 0, max_sigma = 0, work = 0;
    std::vector<double> sigma_measured;
    std::vector<double> f_old(3 * hs.cloud.n_owned(), 0.0), u_old(3 * hs.cloud.n_owned(), 0.0);
    for (const double eps : path)
      {
        const double q_tr = q + c1 * (eps - eps_old), Y = Y0 + H * ep;
        if (std::abs(q_tr) > Y)
          {
            const double a = (std::abs(q_tr) - Y) / (3 * G + H);
            ep += a;
            q = (q_tr > 0 ? 1 : -1) * (Y + H * a);
          }
        else
          q = q_tr;
        eps_old                = eps;
        const double expected  = K * eps + c2 * q;

        hs.set_displacement([&](const Point<3> &x) {
          Tensor<1, 3> d;
          d[0] = eps * x[0];
          return d;
        });
        hs.evaluate();
        double cut = 0, w = 0;
        for (unsigned int i = 0; i < hs.cloud.n_owned(); ++i)
          {
            if (hs.cloud.position(i)[0] > 0.6)
              cut += hs.cloud.volume[i] * hs.force.local_element(3 * i);
            for (unsigned int c = 0; c < 3; ++c)
              {
                const double f = hs.force.local_element(3 * i + c), u = hs.u.local_element(3 * i + c);
                w -= 0.5 * (f + f_old[3 * i + c]) * (u - u_old[3 * i + c]) * hs.cloud.volume[i];
                f_old[3 * i + c] = f;
                u_old[3 * i + c] = u;
              }
          }
        const double sigma = -Utilities::MPI::sum(cut, comm) / A;
        work += Utilities::MPI::sum(w, comm);
        sigma_measured.push_back(sigma);
        max_error = std::max(max_error, std::abs(sigma - expected));
        max_sigma = std::max(max_sigma, std::abs(expected));
        hs.fields->commit();
      }
    report.check("  max |sigma - closed form| / max |sigma| over the path", max_error / max_sigma,
                 max_error / max_sigma < 1e-2, "< 1e-2");
    report.value("  sigma_xx at 4 eps_y", sigma_measured[15]);
    const double eps4 = 4 * eps_y; // beyond the continuum's yield strain Y0 / 2G too
    report.value("  continuum sigma_xx there (c1 = 2G, sqrt(5Q/m) = 2/3)",
                 K * eps4 + 2.0 / 3 * (Y0 + H * 2 * G * (eps4 - Y0 / (2 * G)) / (3 * G + H)));
    const double slope   = (sigma_measured[15] - sigma_measured[19]) / eps_y;
    const double elastic = K + c2 * c1;
    report.check("  unloading slope / (K + sqrt(5Q/m) c1) - 1", slope / elastic - 1,
                 std::abs(slope / elastic - 1) < 1e-2, "|.| < 1e-2");

    double ep_min = 1e300, ep_max = -1e300;
    for (unsigned int i = 0; i < hs.cloud.n_owned(); ++i)
      if (hs.cloud.position(i)[0] > 0.3 && hs.cloud.position(i)[0] < 0.9)
        {
          ep_min = std::min(ep_min, hs.field("eps_plastic_strain", i));
          ep_max = std::max(ep_max, hs.field("eps_plastic_strain", i));
        }
    ep_min = Utilities::MPI::min(ep_min, comm);
    ep_max = Utilities::MPI::max(ep_max, comm);
    const double ep_error = std::max(std::abs(ep_min - ep), std::abs(ep_max - ep)) / ep;
    report.value("  closed-form eps_p", ep);
    report.check("  interior eps_p: max relative error", ep_error, ep_error < 2e-3, "< 2e-3");

    double stored = 0, dissipated = 0;
    for (unsigned int i = 0; i < hs.cloud.n_owned(); ++i)
      {
        stored += hs.cloud.volume[i] * hs.energy[i];
        dissipated += hs.cloud.volume[i] * hs.field("eps_dissipation", i);
      }
    stored     = Utilities::MPI::sum(stored, comm);
    dissipated = Utilities::MPI::sum(dissipated, comm);
    report.value("  work of the internal forces", work);
    report.value("  stored energy", stored);
    report.value("  plastic dissipation", dissipated);
    const double balance = std::abs(work - stored - dissipated) / work;
    report.check("  |work - stored - dissipation| / work", balance, balance < 1e-2, "< 1e-2");
  }
} // namespace

int
main(int argc, char *argv[])
{
  return run_checks(argc, argv, [](const MPI_Comm comm, Report &report) {
    run(comm, report, 0);
    run(comm, report, G);
  });
}
