// What a cut implicit step returns to (Solver/Implicit/Adaptive steps,
// ForceModel::save_damage_state / restore_damage_state): after a run that
// broke bonds, the damage state is saved, the displacement stretched
// (u_c += 0.05 x_c^2) and the damage models run (more bonds break, points are neglected), then the state
// is restored. Cases: qs_notched.prm with Critical damage to neglect material
// point (binary damage, neglect), and softening_bar.prm's PMB bar by Newmark
// (continuous damage). Checks, on every rank:
// - the stretched displacement breaks bonds (the test does something);
// - after the restore every bond's broken flag and d are the saved ones, bit
//   for bit, and so are the neglected points and every point's damage;
// - a damage snapshot taken before the restore is not mistaken for current
//   (save_damage copies again);
// - the damage models on the stretched displacement then change exactly as many
//   bonds as the first time, and leave the same flags: nothing of the undone
//   damage (the neglect bookkeeping included) stays behind.
// Prints PASS/FAIL per check and ALL PASSED.

#include <perideal/discretization/discretization.h>
#include <perideal/model/force_model.h>
#include <perideal/simulation/simulation.h>

#include <deal.II/base/mpi.h>

#include <fstream>
#include <iostream>
#include <sstream>

using namespace perideal;

int
main(int argc, char *argv[])
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                           comm = MPI_COMM_WORLD;
  const bool                               root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  if (argc != 3)
    {
      std::cerr << "usage: physics_damage_restore qs_notched.prm softening_bar.prm" << std::endl;
      return 2;
    }
  const auto read = [](const char *name) {
    std::stringstream text;
    text << std::ifstream(name).rdbuf();
    return text.str();
  };
  std::string notched = read(argv[1]);
  const std::string limit = "set Critical stretch = 0.01";
  const auto        at    = notched.find(limit);
  AssertThrow(at != std::string::npos, dealii::ExcMessage("qs_notched.prm has no '" + limit + "'"));
  notched.insert(at + limit.size(), "\n    set Critical damage to neglect material point = 0.6");
  const std::string softening = read(argv[2]) + "subsection Materials\n  set Names = solid\n  subsection solid\n    "
                                               "set Model = PMB\n    set Density = 1\n    set Bulk modulus = 1\n  "
                                               "end\nend\nsubsection Solver\n  set Type = Newmark\n  set Number of "
                                               "steps = 40\n  set Final time = 1\nend\n";
  const std::vector<std::pair<std::string, std::string>> cases = {{"QuasiStatic, critical stretch, neglect", notched},
                                                                  {"Newmark, Linear softening", softening}};

  unsigned int failures = 0;
  const auto   check    = [&](const std::string &what, const bool ok_here) {
    const bool ok = dealii::Utilities::MPI::min(ok_here ? 1u : 0u, comm) == 1;
    if (root)
      std::cout << "  " << what << ": " << (ok ? "PASS" : "FAIL") << std::endl;
    failures += !ok;
  };
  for (unsigned int c = 0; c < cases.size(); ++c)
    {
      const std::string file = "damage_restore_" + std::to_string(c) + ".prm";
      if (root)
        std::ofstream(file) << cases[c].second;
      MPI_Barrier(comm);
      Simulation simulation(file, comm);
      simulation.run();
      ForceModel       &model = simulation.access().model;
      MechanicalState  &state = simulation.access().state;
      const PointCloud &cloud = simulation.access().discretization.cloud;
      const auto        point_damage = [&]() {
        std::vector<double> d(cloud.n_owned());
        for (unsigned int i = 0; i < d.size(); ++i)
          d[i] = model.point_damage(i);
        return d;
      };

      ForceModel::DamageState saved;
      model.save_damage_state(saved);
      const auto        broken0    = model.broken;
      const auto        damage0    = model.damage;
      const auto        points0    = point_damage();
      const std::size_t neglected0 = model.neglected_points();

      // A stretch everywhere (u_c += 0.05 x_c^2, strain 0.1 x_c): a pulled
      // bar that came apart would only move its pieces under a doubled u.
      for (unsigned int k = 0; k < state.point_entries(); ++k)
        {
          const double x = state.position(k)[state.component(k)];
          state.u(k) += 0.05 * x * x;
        }
      state.displacement.update_ghost_values();
      const std::size_t first = model.break_bonds();
      const auto        broken1 = model.broken;
      const std::size_t neglected1 = dealii::Utilities::MPI::sum(model.neglected_points(), comm);
      ForceModel::DamageSnapshot snapshot;
      model.save_damage(snapshot);

      model.restore_damage_state(saved);
      const std::size_t all_neglected0 = dealii::Utilities::MPI::sum(neglected0, comm);
      if (root)
        std::cout << cases[c].first << ": the stretched displacement changed " << first << " bonds; neglected points "
                  << all_neglected0 << " -> " << neglected1 << std::endl;
      check("the stretched displacement changes bonds", first > 0);
      check("broken flags restored bit for bit", model.broken == broken0);
      check("d restored bit for bit", model.damage == damage0);
      check("neglected points restored", model.neglected_points() == neglected0);
      check("every point's damage restored", point_damage() == points0);
      model.save_damage(snapshot);
      check("a snapshot from before the restore is taken again", snapshot.broken == broken0);
      const std::size_t again = model.break_bonds();
      check("the damage models change as many bonds again (" + std::to_string(again) + ")", again == first);
      check("and leave the same flags", model.broken == broken1);
    }
  if (root)
    std::cout << (failures == 0 ? "ALL PASSED" : std::to_string(failures) + " CHECK(S) FAILED") << std::endl;
  return failures == 0 ? 0 : 1;
}
