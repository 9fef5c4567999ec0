// The templates of doc/developer/templates in a run: `models_templates
// SCENE.prm G_c` runs SCENE (template_split.prm: Template material with
// Template damage) as pd_app would and checks, at its end, each bond's
// decision against the damage template's closed form and the material
// template's history:
// - some bonds broke, not all;
// - a bond is broken exactly when its peak stretch (the material's per-bond
//   history) passed s_c(|xi|) = sqrt(4 G_c / (9 K |xi|)), the stretch at
//   which its energy c s^2 |xi| / 2 (c = 18 K / (pi delta^4)) reaches
//   4 G_c / (pi delta^4); bonds within 1e-9 of s_c are not judged;
// - some broken bond never reached s_c of the shortest bond: the criterion
//   depends on the length, it is no critical stretch;
// - a point's Peak stretch (history) is the largest of its bonds' peaks, and
//   its Bond energy ratio (the damage model's output field) the largest
//   (s / s_c(|xi|))^2 = w / w_c of its intact bonds now (the run ends in
//   tension, at the largest pull), to 1e-9.
// The run's own report goes to run.log, so that standard output holds the
// checks only.
// Its numbers go to numdiff against templates.output on 1 and 2 ranks; the
// material template's conformance is models.Template material.np1/np2
// (models_conformance links the templates too).

#include <perideal/model/force_model.h>
#include <perideal/simulation/simulation.h>

#include "../physics/harness.h"

#include <fstream>

using namespace pdtest;

int
main(int argc, char *argv[])
{
  if (argc != 3)
    {
      std::cerr << "Usage: models_templates SCENE.prm CRITICAL_ENERGY_RELEASE_RATE" << std::endl;
      return 2;
    }
  const std::string scene        = argv[1];
  const double      release_rate = std::stod(argv[2]);
  return run_checks(argc, argv, [&](const MPI_Comm comm, Report &report) {
    perideal::Simulation simulation(scene, comm);
    {
      // std::cout goes back to the terminal before the log closes, also if
      // the run throws.
      std::ofstream log("run.log");
      const std::unique_ptr<std::streambuf, std::function<void(std::streambuf *)>> terminal(
        std::cout.rdbuf(log.rdbuf()), [](std::streambuf *b) { std::cout.rdbuf(b); });
      simulation.run();
    }
    const auto                      access = simulation.access();
    const perideal::PointCloud     &cloud  = access.discretization.cloud;
    const perideal::Bonds          &bonds  = access.discretization.bonds;
    const std::vector<std::uint8_t> &broken = access.model.broken;
    perideal::FieldStore           &fields = access.model.field_store();
    const double K = access.discretization.blocks[0].material->bulk_modulus();
    // NP1: the last evaluation's, which decided the last breaks.
    const double               *peak  = fields.bond("template_bond_peak");
    const perideal::VectorType &point = fields.get("template_peak_stretch");
    const perideal::VectorType &ratio = fields.get("template_energy_ratio");

    const auto s_c = [&](const double length) { return std::sqrt(4 * release_rate / (9 * K * length)); };
    double     shortest = std::numeric_limits<double>::max();
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
        shortest = std::min(shortest, cloud.bond_vector(i, bonds.neighbor[b]).norm());
    shortest = Utilities::MPI::min(shortest, comm);

    double n_broken = 0, unjudged = 0, wrongly_broken = 0, wrongly_intact = 0, below_shortest = 0;
    double point_mismatch = 0, max_point = 0, ratio_error = 0, max_ratio = 0;
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      {
        double largest = 0, closest = 0;
        for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
          {
            double     xi[3], y[3];
            const auto [r0, r] = perideal::bond_geometry(cloud, access.state.displacement.begin(), i,
                                                         bonds.neighbor[b], xi, y);
            const double limit  = s_c(r0);
            const bool   passed = peak[b] > limit;
            largest             = std::max(largest, peak[b]);
            if (!broken[b] && r > r0)
              closest = std::max(closest, std::pow((r - r0) / r0 / limit, 2));
            n_broken += broken[b];
            if (std::abs(peak[b] / limit - 1) < 1e-9)
              ++unjudged;
            else
              {
                wrongly_broken += broken[b] && !passed;
                wrongly_intact += !broken[b] && passed;
              }
            below_shortest += broken[b] && peak[b] < s_c(shortest);
          }
        point_mismatch += point.local_element(i) != largest;
        ratio_error    = std::max(ratio_error, std::abs(ratio.local_element(i) - closest));
        max_point      = std::max(max_point, point.local_element(i));
        max_ratio      = std::max(max_ratio, ratio.local_element(i));
      }
    const auto sum   = [&](const double v) { return Utilities::MPI::sum(v, comm); };
    const double all = sum(double(bonds.n_bonds()));
    n_broken         = sum(n_broken);
    report.line("Template material + Template damage (" + scene.substr(scene.find_last_of('/') + 1) + "): " +
                std::to_string(cloud.n_global()) + " points, " + sci(all, 8) + " bonds (directed)");
    report.check("  broken bonds (directed)", n_broken, n_broken > 0 && n_broken < all, "some, not all");
    report.value("  bonds within 1e-9 of s_c, not judged", sum(unjudged));
    report.check("  broken bonds whose peak stretch stayed below s_c(|xi|)", sum(wrongly_broken),
                 sum(wrongly_broken) == 0, "0");
    report.check("  intact bonds whose peak stretch passed s_c(|xi|)", sum(wrongly_intact), sum(wrongly_intact) == 0,
                 "0");
    report.check("  broken bonds that never reached s_c(shortest bond) = " + sci(s_c(shortest), 6),
                 sum(below_shortest), sum(below_shortest) > 0, "> 0: no critical stretch");
    report.check("  points whose Peak stretch is not their bonds' largest peak", sum(point_mismatch),
                 sum(point_mismatch) == 0, "0");
    report.value("  max Peak stretch", Utilities::MPI::max(max_point, comm));
    report.value("  max Bond energy ratio", Utilities::MPI::max(max_ratio, comm));
    report.below("  max |Bond energy ratio - largest (s / s_c)^2 of the intact bonds|",
                 Utilities::MPI::max(ratio_error, comm), 1e-9);
  });
}
