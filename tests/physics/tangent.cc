// The analytic tangents of PMB and LPS against central finite differences of
// the force (Tangent::add_finite_differences), on a 6 x 4 x 4 box under a
// rank-independent pseudo-random displacement of 5% of the spacing (large
// enough that the geometric stiffness matters). Checks per case:
//   max |K_analytic - K_fd| / max |K_analytic| < 1e-6  (central differences
//       with epsilon = 1e-6 h: truncation ~1e-12, round-off ~1e-9)
//   |z.Kx - x.Kz| / (|z| |Kx|) < 1e-12 for two random x, z (K is symmetric:
//       both models derive from a strain energy)
// The Frobenius norm and the quadratic forms printed compare 1 and 2 ranks
// (stored output, numdiff). With the argument "damaged" the same cases run
// with a continuous bond damage d in [0, 1) per bond (a function of both
// points' hashes: the same for both halves and on any number of ranks): the
// tangent at fixed d, each bond scaled by 1 - d, is then the derivative of
// the force, and still symmetric.

#include <perideal/solver/tangent.h>

#include <deal.II/lac/trilinos_vector.h>

#include "harness.h"

using namespace dealii;

namespace
{
  void
  fill_random(const pdtest::Harness &h, TrilinosWrappers::MPI::Vector &x, const unsigned int salt)
  {
    for (unsigned int i = 0; i < h.cloud.n_owned(); ++i)
      for (unsigned int c = 0; c < 3; ++c)
        x[3 * h.cloud.gid[i] + c] = pdtest::noise(h.cloud.hash(i), 3 * salt + c);
    x.compress(VectorOperation::insert);
  }

  void
  check_case(const MPI_Comm comm, pdtest::Report &report, const std::string &name, const pdtest::MaterialSpec &spec,
             const bool damaged)
  {
    const double   spacing = 0.25;
    pdtest::Harness h(comm, Point<3>(0, 0, 0), Point<3>(1.5, 1, 1), {{6, 4, 4}}, 2.015 * spacing, spec);
    if (damaged)
      {
        h.damage.resize(h.bonds.n_bonds());
        for (unsigned int i = 0; i < h.cloud.n_owned(); ++i)
          for (std::size_t b = h.bonds.offsets[i]; b < h.bonds.offsets[i + 1]; ++b)
            h.damage[b] = 0.5 * (1 + pdtest::noise(h.cloud.hash(i) ^ h.cloud.hash(h.bonds.neighbor[b]), 7));
      }
    h.set_random_displacement(0.05 * spacing);
    h.evaluate(false);

    const std::vector<std::uint8_t> free(3 * h.cloud.n_local(), 0);
    perideal::Tangent               analytic, fd;
    analytic.reinit(h.cloud, h.bonds, h.material->coupling_hops(), comm);
    const bool has = h.material->add_tangent(h.state(false), h.points, analytic.begin(free));
    analytic.finish();
    report.check(name + ": has an analytic tangent", has, has, "true");

    fd.reinit(h.cloud, h.bonds, h.material->coupling_hops(), comm);
    fd.begin(free);
    fd.add_finite_differences(h.u, h.force, [&] { h.evaluate(false); }, 1e-6 * spacing, h.material->coupling_hops() * h.horizon);
    fd.finish();
    report.line(name + ": finite differences with " + std::to_string(fd.n_colours) + " colours");

    double max_a = 0, max_diff = 0;
    for (const auto row : analytic.owned)
      for (auto it = analytic.matrix.begin(row); it != analytic.matrix.end(row); ++it)
        {
          max_a    = std::max(max_a, std::abs(it->value()));
          max_diff = std::max(max_diff, std::abs(it->value() - fd.matrix.el(row, it->column())));
        }
    max_a    = Utilities::MPI::max(max_a, comm);
    max_diff = Utilities::MPI::max(max_diff, comm);
    report.check(name + ": max |K - K_fd| / max |K|", max_diff / max_a, max_diff < 1e-6 * max_a, "< 1e-6");

    TrilinosWrappers::MPI::Vector x(analytic.owned, comm), z(x), Kx(x), Kz(x);
    fill_random(h, x, 1);
    fill_random(h, z, 2);
    analytic.matrix.vmult(Kx, x);
    analytic.matrix.vmult(Kz, z);
    const double asym = std::abs(z * Kx - x * Kz) / (z.l2_norm() * Kx.l2_norm());
    report.check(name + ": |z.Kx - x.Kz| / (|z| |Kx|)", asym, asym < 1e-12, "< 1e-12");
    report.value(name + ": Frobenius norm of K", analytic.matrix.frobenius_norm());
    report.value(name + ": x.Kx", x * Kx);
    report.value(name + ": nonzeros", analytic.matrix.n_nonzero_elements());
  }
} // namespace

int
main(int argc, char *argv[])
{
  const bool damaged = argc > 1 && std::string(argv[1]) == "damaged";
  return pdtest::run_checks(argc, argv, [damaged](const MPI_Comm comm, pdtest::Report &report) {
    const std::string d = damaged ? ", damaged" : "";
    check_case(comm, report, "PMB" + d, {"PMB", {{"Density", "1"}, {"Bulk modulus", "1"}}}, damaged);
    // G = 0.6 K (nu = 1/4) would switch the dilatation coupling off (3K = 5G).
    check_case(comm, report, "LPS nu = 0.34" + d,
               {"LPS", {{"Density", "1"}, {"Bulk modulus", "1"}, {"Shear modulus", "0.35"}}}, damaged);
    check_case(comm, report, "LPS omega = exp(-r*r), nu = 0.4" + d,
               {"LPS",
                {{"Density", "1"}, {"Bulk modulus", "1"}, {"Shear modulus", "0.2143"}, {"Influence function", "exp(-r*r)"}}},
               damaged);
  });
}
