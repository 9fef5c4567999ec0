// Wave speed in a bar (LPS) against sqrt(E/rho), E = 9 K G / (3 K + G).
//
// Method: the fundamental longitudinal mode of a free-free bar 1 x 0.2 x 0.2,
// u_x = A cos(pi x) at rest at t = 0 (A = 1e-6: linear), integrated by
// velocity-Verlet as the core does (lumped mass, dt = half the stable
// estimate). The modal coordinate q(t) = sum V u_x cos(pi x) / sum V cos^2
// goes as A cos(omega t); its first two zero crossings (linear interpolation,
// error O(dt^2)) give omega = pi / (t_2 - t_1) and c = omega L / pi.
// K = 1, G = 0.375 (nu = 1/3, so 3K - 5G != 0 and the dilatation term of the
// LPS force takes part), rho = E = 1: c0 = sqrt(E/rho) = 1.
//
// Expected: the continuum bar has c = c0 (1 - nu^2 pi^2 r_p^2 / (2 L^2))
// (Rayleigh-Love lateral inertia, r_p^2 = 0.2^2/6: -0.37%), c_RL below. On
// top of that the peridynamic bar differs by
// - the surface effect: points within a horizon of the four long faces have
//   truncated families with a smaller weighted volume m, so 15G/m and the
//   bar stiffen; this is O(delta / width), measured c/c0 - 1 = 0.26 delta/0.2
//   (nu = 1/3; 0.19 at nu = 0, 0.23 at nu = 1/4). It is a property of LPS,
//   not a bug: the interior force is checked exactly by lps_homogeneous.
//   (A 1 x 0.05 x 0.05 bar of 3 cells across with horizon 3.015 h is 27% too
//   fast for this reason; too thin for this test.)
// - the cubic lattice: horizon 1.5 h makes the LPS quadrature exact for the
//   axial and shear moduli of a complete family (3.015 h does not: -17% axial
//   deviatoric stiffness), so the bulk limit is the continuum one.
// - dispersion O((k delta)^2), k delta <= 0.16: below 0.1%.
// Checks: (1) for two resolutions (6 and 10 cells across, horizon 1.5 h)
// c_RL < c < c0 (1 + 0.5 delta/0.2): stiffer, by the bounded surface effect;
// (2) the linear extrapolation to delta -> 0 (the surface effect is linear in
// delta) matches c_RL within 1% (the O(delta^2) rest moves it by ~0.3%:
// measured on 4, 6, 8, 10, 12 cells across).

#include "harness.h"

using namespace pdtest;

namespace
{
  struct Measurement
  {
    double c, delta;
  };

  Measurement
  measure(const MPI_Comm comm, Report &report, const unsigned int ny, const double K, const double G)
  {
    const double       L = 1, W = 0.2, E = 9 * K * G / (3 * K + G), rho = E; // c0 = 1
    const unsigned int nx = 5 * ny;
    const double       h = W / ny, horizon = 1.5 * h;
    Harness            harness(comm, Point<3>(0, 0, 0), Point<3>(L, W, W), {{nx, ny, ny}}, horizon,
                    {"LPS", {{"Density", Utilities::to_string(rho, 17)},
                             {"Bulk modulus", Utilities::to_string(K, 17)},
                             {"Shear modulus", Utilities::to_string(G, 17)}}});

    const unsigned int  n  = harness.cloud.n_owned();
    const double        dt = 0.5 * harness.stable_time_step();
    const double        A  = 1e-6;
    std::vector<double> u(3 * n, 0.0), v(3 * n, 0.0), f(3 * n), shape(n);
    double              norm = 0;
    for (unsigned int i = 0; i < n; ++i)
      {
        shape[i] = std::cos(M_PI * harness.cloud.X[3 * i] / L);
        u[3 * i] = A * shape[i];
        norm += harness.cloud.volume[i] * shape[i] * shape[i];
      }
    norm        = Utilities::MPI::sum(norm, comm);
    auto modal = [&]() {
      double q = 0;
      for (unsigned int i = 0; i < n; ++i)
        q += harness.cloud.volume[i] * u[3 * i] * shape[i];
      return Utilities::MPI::sum(q, comm) / norm;
    };
    auto force = [&]() {
      harness.set_displacement(u);
      harness.evaluate(false);
      for (unsigned int k = 0; k < 3 * n; ++k)
        f[k] = harness.force.local_element(k);
    };
    force();
    std::vector<double> crossings;
    double              q_old = modal(), t = 0;
    while (crossings.size() < 2 && t < 3 * L)
      {
        for (unsigned int k = 0; k < 3 * n; ++k)
          {
            v[k] += 0.5 * dt * f[k] / rho;
            u[k] += dt * v[k];
          }
        force();
        for (unsigned int k = 0; k < 3 * n; ++k)
          v[k] += 0.5 * dt * f[k] / rho;
        t += dt;
        const double q = modal();
        if ((q_old > 0) != (q > 0))
          crossings.push_back(t - dt * q / (q - q_old));
        q_old = q;
      }
    AssertThrow(crossings.size() == 2, ExcMessage("no two zero crossings by t = 3 L"));
    const double       c = L / (crossings[1] - crossings[0]);
    std::ostringstream o;
    o << std::setprecision(8) << nx << " x " << ny << " x " << ny << " cells, horizon " << horizon << ": "
      << harness.cloud.n_global() << " points, dt " << dt << ", q = 0 at t = " << crossings[0] << ", "
      << crossings[1];
    report.line(o.str());
    return {c, horizon};
  }
} // namespace

int
main(int argc, char *argv[])
{
  return run_checks(argc, argv, [](const MPI_Comm comm, Report &report) {
    const double K = 1, G = 0.375, W = 0.2, L = 1;
    const double nu   = (3 * K - 2 * G) / (2 * (3 * K + G));
    const double c_RL = 1 - nu * nu * M_PI * M_PI * (W * W / 6) / (2 * L * L);
    report.line("LPS bar 1 x 0.2 x 0.2, nu = 1/3, sqrt(E/rho) = 1; Rayleigh-Love c_RL = " + sci(c_RL, 6));
    std::vector<Measurement> m;
    for (const unsigned int ny : {6u, 10u})
      {
        m.push_back(measure(comm, report, ny, K, G));
        const double upper = 1 + 0.5 * m.back().delta / W;
        report.check("  c / sqrt(E/rho)", m.back().c, m.back().c > c_RL && m.back().c < upper,
                     "in (c_RL, 1 + 0.5 delta/0.2 = " + sci(upper, 4) + "): surface stiffening");
      }
    const double c_limit = m[1].c - (m[0].c - m[1].c) / (m[0].delta - m[1].delta) * m[1].delta;
    report.check("extrapolated to delta -> 0: c / c_RL", c_limit / c_RL, std::abs(c_limit / c_RL - 1) < 0.01,
                 "1 +- 0.01");
  });
}
