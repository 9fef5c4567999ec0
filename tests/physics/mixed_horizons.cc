// Two blocks of one material whose horizons differ by a factor 2: a point of
// the wide block holds neighbors in the narrow block whose families do not
// hold it back. Peridigm's semantics: a point's state sums over its own
// family, and a bond in one family only still acts on both of its ends.
// Checks, for PMB, LPS (omega = 1) and LPS (omega = 1 - r):
//
// 1. Newton's third law: under a non-affine displacement (|grad u| ~ 1e-2)
//    the internal forces sum to zero, |sum_i V_i f_i| / sum_i |V_i f_i| <
//    1e-12 (round-off of ~10^3 terms is ~1e-15; a missing reaction gives
//    0.01-0.2).
// 2. The force is the energy's derivative, V_k f_k = -dE/du_k with E =
//    sum_i V_i W_i, by central differences (step 1e-8 against u ~ 1e-3:
//    truncation ~1e-16, round-off ~1e-8 of the force) at the points of one
//    line across the interface: max error / max |V f| < 1e-6. Then the
//    explicit energy balance holds as with one horizon.
// 3. The analytic tangent against finite differences of the force
//    (Tangent::add_finite_differences) on a smaller box, max |K - K_fd| /
//    max |K| < 1e-6, and symmetric (|z.Kx - x.Kz| / (|z| |Kx|) < 1e-12),
//    as tangent.cc for one horizon: the LPS 2-hop sparsity holds the
//    couplings through a one-sided bond.
// The energy and the Frobenius norm printed compare 1 and 2 ranks.

#include <perideal/solver/tangent.h>

#include <deal.II/lac/trilinos_vector.h>

#include "harness.h"

using namespace pdtest;

namespace
{
  const std::vector<std::pair<std::string, MaterialSpec>> models = {
    {"PMB", {"PMB", {{"Density", "1"}, {"Bulk modulus", "1"}}}},
    {"LPS omega = 1", {"LPS", {{"Density", "1"}, {"Bulk modulus", "1"}, {"Shear modulus", "0.35"}}}},
    {"LPS omega = 1 - r",
     {"LPS", {{"Density", "1"}, {"Bulk modulus", "1"}, {"Shear modulus", "0.35"}, {"Influence function", "1 - r"}}}}};

  Tensor<1, 3>
  non_affine(const Point<3> &x)
  {
    Tensor<1, 3> d;
    d[0] = 1e-3 * std::sin(7 * x[1]) + 2e-3 * x[0] * x[2] + 1e-3 * x[0] * x[0];
    d[1] = -1e-3 * std::cos(5 * x[0] + x[2]);
    d[2] = 1.5e-3 * x[1] * x[1] - 1e-3 * x[0] * x[1];
    return d;
  }

  double
  total_energy(Harness &h)
  {
    h.evaluate(true);
    double e = 0;
    for (unsigned int i = 0; i < h.cloud.n_owned(); ++i)
      e += h.cloud.volume[i] * h.energy[i];
    return Utilities::MPI::sum(e, h.comm);
  }

  void
  balance_and_energy(const MPI_Comm comm, Report &report, const std::string &name, const MaterialSpec &spec)
  {
    // 2 x 1 x 1, h = 1/8; block 0 (x < 1) horizon 3.015 h, block 1 half that.
    const double h = 0.125, delta = 3.015 * h;
    Harness      H(comm, Point<3>(0, 0, 0), Point<3>(2, 1, 1), {{16, 8, 8}}, delta, spec, {}, false,
              {{false, false, false}}, SecondBlock{1.0, delta / 2});
    H.set_displacement(non_affine);
    const double E = total_energy(H);
    Tensor<1, 3> sum;
    double       scale = 0, largest = 0;
    for (unsigned int i = 0; i < H.cloud.n_owned(); ++i)
      {
        const Tensor<1, 3> Vf = H.cloud.volume[i] * H.force_of(i);
        sum += Vf;
        scale += Vf.norm();
        largest = std::max(largest, Vf.norm());
      }
    for (unsigned int d = 0; d < 3; ++d)
      sum[d] = Utilities::MPI::sum(sum[d], comm);
    scale   = Utilities::MPI::sum(scale, comm);
    largest = Utilities::MPI::max(largest, comm);
    report.below(name + ": |sum V f| / sum |V f|", sum.norm() / scale, 1e-12);
    report.value(name + ": strain energy", E);

    // -dE/du at the points of the line y = z = 7/16 (through both blocks).
    std::vector<Tensor<1, 3>> Vf(H.cloud.n_owned());
    for (unsigned int i = 0; i < H.cloud.n_owned(); ++i)
      Vf[i] = H.cloud.volume[i] * H.force_of(i);
    const double eps   = 1e-8;
    double       error = 0;
    for (unsigned int cell = 0; cell < 16; ++cell)
      {
        const Point<3> x((cell + 0.5) * h, 7 * h / 2, 7 * h / 2);
        int            owner = -1;
        for (unsigned int i = 0; i < H.cloud.n_owned(); ++i)
          if (H.cloud.position(i).distance(x) < 1e-9)
            owner = i;
        for (unsigned int c = 0; c < 3; ++c)
          {
            double dE = 0;
            for (const double sign : {1.0, -1.0})
              {
                if (owner >= 0)
                  H.u.local_element(3 * owner + c) += sign * eps;
                H.u.update_ghost_values();
                dE += sign * total_energy(H);
                if (owner >= 0)
                  H.u.local_element(3 * owner + c) -= sign * eps;
              }
            H.u.update_ghost_values();
            const double local = owner >= 0 ? std::abs(Vf[owner][c] + dE / (2 * eps)) : 0.0;
            error              = std::max(error, Utilities::MPI::max(local, comm));
          }
      }
    report.below(name + ": max |V f + dE/du| / max |V f| on the line", error / largest, 1e-6);
  }

  void
  tangent(const MPI_Comm comm, Report &report, const std::string &name, const MaterialSpec &spec)
  {
    // 2 x 1 x 1, h = 1/4; block 0 (x < 1) horizon 2.015 h, block 1 half that.
    const double h = 0.25, delta = 2.015 * h;
    Harness      H(comm, Point<3>(0, 0, 0), Point<3>(2, 1, 1), {{8, 4, 4}}, delta, spec, {}, false,
              {{false, false, false}}, SecondBlock{1.0, delta / 2});
    H.set_random_displacement(0.05 * h);
    H.evaluate(false);

    const std::vector<std::uint8_t> free(3 * H.cloud.n_local(), 0);
    const unsigned int              hops = H.material->coupling_hops();
    perideal::Tangent               analytic, fd;
    analytic.reinit(H.cloud, H.bonds, hops, comm);
    const bool has = H.add_tangent(analytic.begin(free));
    analytic.finish();
    report.check(name + ": has an analytic tangent", has, has, "true");
    fd.reinit(H.cloud, H.bonds, hops, comm);
    fd.begin(free);
    fd.add_finite_differences(H.u, H.force, [&] { H.evaluate(false); }, 1e-6 * h, hops * delta);
    fd.finish();

    double max_a = 0, max_diff = 0;
    for (const auto row : analytic.owned)
      for (auto it = analytic.matrix.begin(row); it != analytic.matrix.end(row); ++it)
        {
          max_a    = std::max(max_a, std::abs(it->value()));
          max_diff = std::max(max_diff, std::abs(it->value() - fd.matrix.el(row, it->column())));
        }
    max_a    = Utilities::MPI::max(max_a, comm);
    max_diff = Utilities::MPI::max(max_diff, comm);
    report.below(name + ": max |K - K_fd| / max |K|", max_diff / max_a, 1e-6);

    TrilinosWrappers::MPI::Vector x(analytic.owned, comm), z(x), Kx(x), Kz(x);
    for (unsigned int i = 0; i < H.cloud.n_owned(); ++i)
      for (unsigned int c = 0; c < 3; ++c)
        {
          x[3 * H.cloud.gid[i] + c] = noise(H.cloud.hash(i), 3 + c);
          z[3 * H.cloud.gid[i] + c] = noise(H.cloud.hash(i), 6 + c);
        }
    x.compress(VectorOperation::insert);
    z.compress(VectorOperation::insert);
    analytic.matrix.vmult(Kx, x);
    analytic.matrix.vmult(Kz, z);
    report.below(name + ": |z.Kx - x.Kz| / (|z| |Kx|)", std::abs(z * Kx - x * Kz) / (z.l2_norm() * Kx.l2_norm()),
                 1e-12);
    report.value(name + ": Frobenius norm of K", analytic.matrix.frobenius_norm());
  }
} // namespace

int
main(int argc, char *argv[])
{
  return run_checks(argc, argv, [](const MPI_Comm comm, Report &report) {
    for (const auto &[name, spec] : models)
      balance_and_energy(comm, report, name, spec);
    for (const auto &[name, spec] : models)
      tangent(comm, report, name, spec);
  });
}
