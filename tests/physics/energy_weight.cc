// Energy weights (Material::weight_energy), the building block of the
// energy-based FE-PD coupling (doc/coupling.md): E = sum_i w_i V_i W_i.
//
// Unit cube, 8^3 points, horizon 3.015 h; PMB (K = 1), LPS (K = 1, G = 0.35:
// not 0.6, where 3K - 5G = 0 would hide the dilatation term)
// with omega = 1 and omega = 1 - r. Weight field
//   w(x) = clamp(0.5 + 1.2 (x - 0.5) + 0.1 sin(7y + 3z), 0, 1)
// (0 on the left, 1 on the right, a band between), and a non-affine
// displacement of amplitude 1e-3. Checked for each model:
// 1. momentum: |sum_i V_i f_i| below 1e-13 of sum_i V_i |f_i|: the weighted
//    forces are still pairwise balanced;
// 2. the weighted total energy equals sum_i w_i V_i W_i of the unweighted
//    energy densities W_i at the same displacement (relative 1e-13), and
//    f = -dE/du: central differences (step 1e-7) of it at 3 points x 3
//    components against V_k f_k, within 1e-6 of max V |f|;
// 3. w = 1 everywhere gives the unweighted forces and energy (relative 1e-14).
// Round-off values differ between rank counts: lines print PASS/FAILED only.

#include "harness.h"

using namespace pdtest;

namespace
{
  const Point<3> lower(0, 0, 0), upper(1, 1, 1);
  const unsigned int n       = 8;
  const double       horizon = 3.015 / n;

  double
  band(const Point<3> &x)
  {
    return std::clamp(0.5 + 1.2 * (x[0] - 0.5) + 0.1 * std::sin(7 * x[1] + 3 * x[2]), 0.0, 1.0);
  }

  Tensor<1, 3>
  wavy(const Point<3> &x)
  {
    const double A = 1e-3;
    Tensor<1, 3> d;
    d[0] = A * std::sin(2 * x[0] + x[1]) + A * x[2] * x[2];
    d[1] = A * std::cos(3 * x[2] - x[0]) * x[1];
    d[2] = A * std::sin(5 * x[0] * x[1]) - 0.5 * A * x[2];
    return d;
  }

  double
  total_energy(Harness &h)
  {
    h.evaluate(true);
    double E = 0;
    for (unsigned int i = 0; i < h.cloud.n_owned(); ++i)
      E += h.cloud.volume[i] * h.energy[i];
    return Utilities::MPI::sum(E, h.comm);
  }

} // namespace

int
main(int argc, char *argv[])
{
  return run_checks(argc, argv, [](const MPI_Comm comm, Report &report) {

    for (const auto &[name, spec, G_continuum] : coupling_models(true))
      {
        report.line(name + ":");
        Harness weighted(comm, lower, upper, {{n, n, n}}, horizon, spec, band);
        weighted.set_displacement(wavy);
        weighted.evaluate(true);
        const unsigned int n_owned = weighted.cloud.n_owned();

        // 1. Momentum.
        double sums[4] = {0, 0, 0, 0};
        for (unsigned int i = 0; i < n_owned; ++i)
          {
            const Tensor<1, 3> Vf = weighted.cloud.volume[i] * weighted.force_of(i);
            for (unsigned int c = 0; c < 3; ++c)
              sums[c] += Vf[c];
            sums[3] += Vf.norm();
          }
        Utilities::MPI::sum(ArrayView<const double>(sums, 4), comm, ArrayView<double>(sums, 4));
        report.below("  |sum V f| / sum V |f|", std::sqrt(sums[0] * sums[0] + sums[1] * sums[1] + sums[2] * sums[2]) / sums[3],
              1e-13);

        // 2. The weighted energy, then f = -dE/du at points near three
        //    positions (one in the band).
        Harness plain(comm, lower, upper, {{n, n, n}}, horizon, spec);
        plain.set_displacement(wavy);
        const double E_plain = total_energy(plain);
        double       E_expected = 0;
        for (unsigned int i = 0; i < plain.cloud.n_owned(); ++i)
          E_expected += band(plain.cloud.position(i)) * plain.cloud.volume[i] * plain.energy[i];
        E_expected = Utilities::MPI::sum(E_expected, comm);
        report.below("  |E - sum w V W_unweighted| / E", std::abs(total_energy(weighted) - E_expected) / E_expected, 1e-13);
        weighted.evaluate(true);

        double largest = 0;
        for (unsigned int i = 0; i < n_owned; ++i)
          largest = std::max(largest, weighted.cloud.volume[i] * weighted.force_of(i).norm());
        largest = Utilities::MPI::max(largest, comm);
        std::vector<double> Vf(3 * n_owned);
        for (unsigned int i = 0; i < n_owned; ++i)
          for (unsigned int c = 0; c < 3; ++c)
            Vf[3 * i + c] = weighted.cloud.volume[i] * weighted.force.local_element(3 * i + c);
        double worst = 0;
        for (const Point<3> &target : {Point<3>(0.5, 0.5, 0.5), Point<3>(0.3, 0.2, 0.8), Point<3>(0.9, 0.6, 0.1)})
          {
            // The owned point nearest the target; the rank with the smallest
            // distance (then the lowest rank) perturbs it.
            unsigned int k = 0;
            double       d = std::numeric_limits<double>::max();
            for (unsigned int i = 0; i < n_owned; ++i)
              if (weighted.cloud.position(i).distance(target) < d)
                d = weighted.cloud.position(i).distance(target), k = i;
            const double d_min = Utilities::MPI::min(d, comm);
            const unsigned int rank = Utilities::MPI::this_mpi_process(comm);
            const unsigned int owner =
              Utilities::MPI::min(d == d_min ? rank : Utilities::MPI::n_mpi_processes(comm), comm);
            for (unsigned int c = 0; c < 3; ++c)
              {
                const double step = 1e-7;
                double       E[2];
                for (const int side : {0, 1})
                  {
                    if (rank == owner)
                      weighted.u.local_element(3 * k + c) += side == 0 ? step : -2 * step;
                    weighted.u.update_ghost_values();
                    E[side] = total_energy(weighted);
                  }
                if (rank == owner)
                  weighted.u.local_element(3 * k + c) += step;
                weighted.u.update_ghost_values();
                const double fd = -(E[0] - E[1]) / (2 * step);
                const double error = rank == owner ? std::abs(fd - Vf[3 * k + c]) : 0.0;
                worst = std::max(worst, Utilities::MPI::max(error, comm));
              }
          }
        report.below("  max |V f + dE/du| / max V |f| (central differences, 3 points x 3 components)", worst / largest,
              1e-6);

        // 3. Weight 1 everywhere = unweighted.
        Harness ones(comm, lower, upper, {{n, n, n}}, horizon, spec, [](const Point<3> &) { return 1.0; });
        ones.set_displacement(wavy);
        const double E1 = total_energy(ones), E0 = E_plain;
        plain.evaluate(true);
        double       df = 0, f0 = 0;
        for (unsigned int i = 0; i < plain.cloud.n_owned(); ++i)
          {
            df = std::max(df, (ones.force_of(i) - plain.force_of(i)).norm());
            f0 = std::max(f0, plain.force_of(i).norm());
          }
        df = Utilities::MPI::max(df, comm);
        f0 = Utilities::MPI::max(f0, comm);
        report.below("  weight 1: max |f - f_unweighted| / max |f|", df / f0, 1e-14);
        report.below("  weight 1: |E - E_unweighted| / E", std::abs(E1 - E0) / E0, 1e-14);
      }
  });
}
