// Periodic directions (Discretization/Periodic directions): a box periodic in
// x, y and z is a piece of an unbounded lattice, so every point must see the
// same family and a plane wave must be an exact mode with the lattice's own
// stiffness, at points next to the faces as in the middle.
//
// Box 1.25 x 1.125 x 1.5, h = 1/8 (10 x 9 x 12 cells: three different
// periods), horizon 3.015 h. Checked, on 1 and 2 ranks (the 2-rank run has
// families across ranks and across the periodic faces at once):
//
// 1. Every family has the 122 bonds of the interior lattice (whole cells) and
//    its bond vectors sum to zero (|sum xi| below 1e-12 h).
// 2. Plane waves u = A e_a cos(k x_b), k = 2 pi / L_b, A = 1e-8: the force
//    density is f = -D A e_a cos(k x_b) at every point, with D the lattice sum
//    (linearized models, omega = 1, V = h^3, n = xi/|xi|):
//      PMB, longitudinal:  D = sum c n_a^2/|xi| (1 - cos(k xi_b)) V
//      LPS, transverse:    D = (30 G/m) sum n_a^2 (1 - cos(k xi_b)) V
//      LPS, longitudinal:  D = (30 G/m) S2 + 3 (3K - 5G) S1^2 / m^2,
//                          S1 = sum |xi| n_b sin(k xi_b) V, S2 = sum n_b^2 (1 - cos(k xi_b)) V
//    (the last from theta_i = -(3/m) A S1 sin(k x_b); they tend to 9K/5,
//    G, K + 4G/3 times k^2 for long waves). Bound: at every point
//    |f_a / A + D cos(k x_b)| below 1e-6 D (the geometric nonlinearity is of
//    relative size A k / h ~ 4e-7; the round-off of |y| - |xi| at this
//    amplitude ~1e-9), the other components below 1e-6 D A.
// 3. Partial volumes: every point's family fills the ball (sum beta V =
//    4/3 pi delta^3 - V_i within 1e-5 of the ball, as in partial_volumes),
//    all points alike within 1e-12, and the PMB longitudinal wave is again
//    one mode (every point within 1e-6 D of the least-squares D).
// 4. A box too short for two horizons along y (6 cells at 3.015 h) stops
//    with the error naming Discretization/Periodic directions.

#include "harness.h"

using namespace pdtest;

namespace
{
  const double                      h = 0.125, delta = 3.015 * h, K = 1.3, G = 0.7, A = 1e-8;
  const Point<3>                    lower(0, 0, 0), upper(1.25, 1.125, 1.5);
  const std::array<unsigned int, 3> cells{{10, 9, 12}};
  const std::array<bool, 3>         all_periodic{{true, true, true}};

  /// Applies u = A e_a cos(k x_b) and returns the largest |f_a / A + D cos(k x_b)| / D
  /// over the points and the largest other component over D A. @p D <= 0:
  /// the least-squares fit of the points is used and returned in D.
  std::pair<double, double>
  mode(Harness &t, const unsigned int a, const unsigned int b, double &D)
  {
    const double k = 2 * M_PI / (upper[b] - lower[b]);
    t.set_displacement([&](const Point<3> &x) {
      Tensor<1, 3> u;
      u[a] = A * std::cos(k * x[b]);
      return u;
    });
    t.evaluate(false);
    std::vector<double> shape, response;
    double              other = 0, fc = 0, cc = 0;
    for (unsigned int i = 0; i < t.cloud.n_owned(); ++i)
      {
        const Tensor<1, 3> f = t.force_of(i);
        shape.push_back(std::cos(k * t.cloud.position(i)[b]));
        response.push_back(f[a] / A);
        fc += response.back() * shape.back();
        cc += shape.back() * shape.back();
        for (unsigned int c = 0; c < 3; ++c)
          if (c != a)
            other = std::max(other, std::abs(f[c]));
      }
    if (D <= 0)
      D = -Utilities::MPI::sum(fc, t.comm) / Utilities::MPI::sum(cc, t.comm);
    double worst = 0;
    for (unsigned int p = 0; p < shape.size(); ++p)
      worst = std::max(worst, std::abs(response[p] + D * shape[p]) / D);
    return {Utilities::MPI::max(worst, t.comm), Utilities::MPI::max(other, t.comm) / (D * A)};
  }
} // namespace

int
main(int argc, char **argv)
{
  return run_checks(argc, argv, [](const MPI_Comm comm, Report &report) {
    const double V       = h * h * h;
    const auto   lattice = complete_family(h, delta, V);
    const auto  &xi      = lattice.xi;
    const double m       = lattice.m;
    const double c       = 18 * K / (M_PI * std::pow(delta, 4));
    std::ostringstream out;
    out << std::scientific << std::setprecision(6);
    // Lattice sums of the three modes (the tensor indices: a = displacement, b = wave).
    const auto lattice_D = [&](const std::string &model, const unsigned int a, const unsigned int b) {
      const double k  = 2 * M_PI / (upper[b] - lower[b]);
      double       S1 = 0, S2 = 0, P = 0;
      for (const auto &e : xi)
        {
          const double r = e.norm(), na = e[a] / r, nb = e[b] / r;
          S1 += r * nb * std::sin(k * e[b]) * V;
          S2 += na * na * (1 - std::cos(k * e[b])) * V;
          P += c * na * na / r * (1 - std::cos(k * e[b])) * V;
        }
      if (model == "PMB")
        return P;
      return a == b ? 30 * G / m * S2 + 3 * (3 * K - 5 * G) * S1 * S1 / (m * m) : 30 * G / m * S2;
    };
    const auto print = [&]() {
      std::string text = out.str();
      if (!text.empty() && text.back() == '\n')
        text.pop_back();
      report.line(text);
      out.str("");
    };

    const MaterialSpec pmb{"PMB", {{"Density", "1"}, {"Bulk modulus", std::to_string(K)}}};
    const MaterialSpec lps{"LPS", {{"Density", "1"}, {"Bulk modulus", std::to_string(K)}, {"Shear modulus", std::to_string(G)}}};

    out << "Box 10 x 9 x 12 cells, h = 1/8, horizon 3.015 h, periodic in x, y, z; lattice family "
                << xi.size() << " bonds\n";
    print();
    {
      Harness      t(comm, lower, upper, cells, delta, pmb, {}, false, all_periodic);
      unsigned int fewest = 1000, most = 0;
      double       largest_sum = 0;
      for (unsigned int i = 0; i < t.cloud.n_owned(); ++i)
        {
          const unsigned int n = t.bonds.offsets[i + 1] - t.bonds.offsets[i];
          fewest               = std::min(fewest, n);
          most                 = std::max(most, n);
          Tensor<1, 3> sum;
          for (std::size_t b = t.bonds.offsets[i]; b < t.bonds.offsets[i + 1]; ++b)
            sum += t.cloud.bond_vector(i, t.bonds.neighbor[b]);
          largest_sum = std::max(largest_sum, sum.norm());
        }
      fewest      = Utilities::MPI::min(fewest, t.comm);
      most        = Utilities::MPI::max(most, t.comm);
      largest_sum = Utilities::MPI::max(largest_sum, t.comm);
      out << "1. families: " << t.cloud.n_global() << " points, " << fewest << " to " << most << " bonds each\n";
      print();
      report.check("bonds of the smallest and of the largest family (lattice " + std::to_string(xi.size()) + ")", most,
                   fewest == xi.size() && most == xi.size(), "both == lattice");
      report.below("largest |sum of a family's bond vectors| / h", largest_sum / h, 1e-12);

      out << "2. plane waves u = A e_a cos(k x_b), k = 2 pi / L_b, A = 1e-8:\n";
      print();
      double D = lattice_D("PMB", 1, 1);
      auto [worst, other] = mode(t, 1, 1, D);
      out << "  PMB longitudinal along y: lattice D = " << D << " (long waves " << 9 * K / 5 << " k^2 = "
                  << 9 * K / 5 * std::pow(2 * M_PI / 1.125, 2) << ")\n";
      print();
      report.below("PMB: max |f_y / A + D cos(k y)| / D", worst, 1e-6);
      report.below("PMB: max |f_x|, |f_z| / (D A)", other, 1e-6);
    }
    {
      Harness t(comm, lower, upper, cells, delta, lps, {}, false, all_periodic);
      for (const auto &[a, b, name] : {std::tuple<unsigned int, unsigned int, std::string>{0, 0, "longitudinal along x"},
                                       std::tuple<unsigned int, unsigned int, std::string>{0, 2, "transverse along z"}})
        {
          double D = lattice_D("LPS", a, b);
          const double k    = 2 * M_PI / (upper[b] - lower[b]);
          auto [worst, other] = mode(t, a, b, D);
          out << "  LPS " << name << ": lattice D = " << D << " (long waves "
                      << (a == b ? K + 4 * G / 3 : G) * k * k << ")\n";
          print();
          report.below("LPS " + name + ": max |f_x / A + D cos(k x_b)| / D", worst, 1e-6);
          report.below("LPS " + name + ": max other components / (D A)", other, 1e-6);
        }
    }
    {
      Harness      t(comm, lower, upper, cells, delta, pmb, {}, true, all_periodic);
      const double ball = 4 * M_PI / 3 * std::pow(delta, 3);
      double       low = 1e300, high = -1e300;
      for (unsigned int i = 0; i < t.cloud.n_owned(); ++i)
        {
          double sum = 0;
          for (std::size_t b = t.bonds.offsets[i]; b < t.bonds.offsets[i + 1]; ++b)
            sum += t.bonds.fraction(b) * t.cloud.volume[t.bonds.neighbor[b]];
          low  = std::min(low, sum);
          high = std::max(high, sum);
        }
      low  = Utilities::MPI::min(low, t.comm);
      high = Utilities::MPI::max(high, t.comm);
      const double fill = (high - (ball - V)) / ball;
      const auto   count = Utilities::MPI::sum(double(t.bonds.n_bonds()), t.comm);
      out << "3. partial volumes: " << count / t.cloud.n_global()
                  << " bonds per point; sum beta V - (ball - V_i) = " << std::setprecision(2) << fill
                  << " of the ball\n" << std::setprecision(6);
      print();
      report.below("|sum beta V - (ball - V_i)| / ball", std::abs(fill), 1e-5);
      report.below("(largest - smallest sum beta V) / largest", (high - low) / high, 1e-12);
      double D            = 0;
      auto [worst, other] = mode(t, 1, 1, D);
      out << "  PMB longitudinal along y: D = " << D << " (whole cells " << lattice_D("PMB", 1, 1) << ")\n";
      print();
      report.below("PMB with partial volumes: max |f_y / A + D cos(k y)| / D", worst, 1e-6);
      report.below("PMB with partial volumes: max |f_x|, |f_z| / (D A)", other, 1e-6);
    }
    {
      report.line("4. a period shorter than two horizons:");
      std::string message;
      try
        {
          Harness t(comm, lower, Point<3>(1.25, 0.75, 1.5), {{10, 6, 12}}, delta, pmb, {}, false,
                    all_periodic);
        }
      catch (const std::exception &e)
        {
          message = e.what();
        }
      const bool named = message.find("Discretization/Periodic directions: the period along y") != std::string::npos;
      report.check("stops with 'Discretization/Periodic directions: the period along y ...'", named, named, "== 1");
    }

  });
}
