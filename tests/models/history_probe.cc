// The model layer's state, through real runs of every integrator:
// - per-point and per-bond history (N, NP1) is committed exactly once per
//   accepted step, never inside a Newton iteration or a line search;
// - per-point tensor fields (9 and 6 components) are ghosted like scalars.
//
// A test-only material, "History probe", is PMB (through the registry) plus:
//   probe_steps (history, per point) and probe_bond_steps (history, per bond):
//     every evaluation sets NP1 = N + 1, so after a run N counts the commits;
//   probe_evaluations (local): counts the evaluations;
//   probe_tensor (stage, 9 components) and probe_symmetric (constant, 6
//     components): functions of a point's position, checked at every bond's
//     far end, ghosts included.
// For each integrator the program runs base.prm (argument 1) with Solver/Type
// set and checks that, at the end, N = the number of steps at every point and
// bond, that implicit runs evaluated more often than they
// committed, and that no ghost tensor differs from its owner's. Prints one
// line per integrator and PASS, or FAIL lines and exits with 1.

#include <perideal/model/force_model.h>
#include <perideal/simulation/simulation.h>

#include <deal.II/base/mpi.h>

#include <fstream>
#include <iostream>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    // What the probe saw, this rank.
    std::size_t evaluations = 0, ghost_checks = 0, ghost_mismatches = 0;

    // Component k of the tensors at position x: distinct per point and per
    // component.
    double
    tensor_value(const double *x, const unsigned int k)
    {
      return (k + 1) * x[0] + (k + 2) * (k + 2) * x[1] - (10 - k) * x[2];
    }
  } // namespace

  namespace
  {
    class HistoryProbe : public Material
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        Registry<Material>::instance().get("PMB", "History probe").declare(prm);
      }

      HistoryProbe()
        : pmb(Registry<Material>::instance().create("PMB", "History probe"))
      {}

      void
      parse_parameters(ParameterHandler &prm, const std::string &path) override
      {
        pmb->parse_parameters(prm, path);
      }
      double
      density() const override
      {
        return pmb->density();
      }
      double
      bulk_modulus() const override
      {
        return pmb->bulk_modulus();
      }
      double
      shear_modulus() const override
      {
        return pmb->shear_modulus();
      }

      std::vector<PointField>
      point_fields() const override
      {
        std::vector<PointField> fields = pmb->point_fields();
        fields.push_back({"probe_steps", FieldUse::history});
        fields.push_back({"probe_evaluations", FieldUse::local});
        fields.push_back({"probe_tensor", FieldUse::stage, 9});
        fields.push_back({"probe_symmetric", FieldUse::constant, 6});
        return fields;
      }
      std::vector<BondField>
      bond_fields() const override
      {
        return {{"probe_bond_steps"}};
      }

      void
      initialize(const ModelState &state, const std::vector<unsigned int> &points) override
      {
        pmb->set_block(block, horizon);
        pmb->initialize(state, points);
        VectorType &s = state.fields.get("probe_symmetric");
        for (const unsigned int i : points)
          for (unsigned int k = 0; k < 6; ++k)
            s.local_element(6 * i + k) = tensor_value(&state.cloud.X[3 * i], k);
      }

      void
      compute_stage(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        pmb->compute_stage(state, points);
        VectorType &t = state.fields.get("probe_tensor");
        for (const unsigned int i : points)
          for (unsigned int k = 0; k < 9; ++k)
            t.local_element(9 * i + k) = tensor_value(&state.cloud.X[3 * i], k);
      }

      void
      compute_force(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        pmb->compute_force(state, points);
        ++evaluations;
        FieldStore       &fields = state.fields;
        const VectorType &n      = fields.old("probe_steps");
        VectorType       &np1    = fields.get("probe_steps");
        VectorType       &count  = fields.get("probe_evaluations");
        const VectorType &t = fields.get("probe_tensor"), &s = fields.get("probe_symmetric");
        const double     *bond_n   = fields.bond_old("probe_bond_steps");
        double           *bond_np1 = fields.bond("probe_bond_steps");
        const unsigned int n_owned = state.cloud.n_owned();
        for (const unsigned int i : points)
          {
            np1.local_element(i) = n.local_element(i) + 1;
            count.local_element(i) += 1;
            for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
              {
                bond_np1[b]          = bond_n[b] + 1;
                const unsigned int j = state.bonds.neighbor[b];
                if (j < n_owned)
                  continue;
                ++ghost_checks;
                for (unsigned int k = 0; k < 9; ++k)
                  ghost_mismatches += t.local_element(9 * j + k) != tensor_value(&state.cloud.X[3 * j], k);
                for (unsigned int k = 0; k < 6; ++k)
                  ghost_mismatches += s.local_element(6 * j + k) != tensor_value(&state.cloud.X[3 * j], k);
              }
          }
      }

      bool
      fuses_stretch_criterion() const override
      {
        return false;
      }
      double
      stable_time_step(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        return pmb->stable_time_step(state, points);
      }
      unsigned int
      coupling_hops() const override
      {
        return pmb->coupling_hops();
      }
      bool
      add_tangent(const ModelState &state, const std::vector<unsigned int> &points, TangentRows &rows) const override
      {
        return pmb->add_tangent(state, points, rows);
      }

    private:
      std::unique_ptr<Material> pmb;
    };
  } // namespace

  PERIDEAL_REGISTER(Material, HistoryProbe, "History probe",
                    "test only: PMB plus history, evaluation and tensor fields (tests/models/history_probe.cc)")
} // namespace perideal

int
main(int argc, char *argv[])
{
  using namespace perideal;
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm comm = MPI_COMM_WORLD;
  const bool     root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  if (argc != 2)
    {
      if (root)
        std::cerr << "usage: models_history_probe base.prm\n";
      return 2;
    }
  std::stringstream base;
  base << std::ifstream(argv[1]).rdbuf();

  struct Case
  {
    std::string  type, solver_keys;
    unsigned int steps;
    bool         implicit;
  };
  const std::vector<Case> cases = {
    {"Verlet", "set Number of steps = 5", 5, false},
    {"QuasiStatic", "set Number of steps = 4", 4, true},
    {"Newmark", "set Number of steps = 4\n  set Final time = 4", 4, true}};

  bool passed = true;
  for (const Case &c : cases)
    {
      const std::string file = "probe_" + c.type + ".prm";
      if (root)
        std::ofstream(file) << base.str() << "subsection Solver\n  set Type = " << c.type << "\n  "
                            << c.solver_keys << "\nend\n";
      MPI_Barrier(comm);
      evaluations = ghost_checks = ghost_mismatches = 0;
      Simulation simulation(file, comm);
      simulation.run();

      FieldStore       &fields     = simulation.access().model.field_store();
      const Bonds      &bonds      = simulation.access().discretization.bonds;
      const unsigned int n_owned   = simulation.access().discretization.cloud.n_owned();
      const VectorType &n          = fields.old("probe_steps");
      const double     *bond_n     = fields.bond_old("probe_bond_steps");
      double            wrong      = 0;
      // N only: an evaluation after the last step (the summary's) may leave
      // a trial NP1 that is never committed.
      for (unsigned int i = 0; i < n_owned; ++i)
        wrong += n.local_element(i) != c.steps;
      for (std::size_t b = 0; b < bonds.n_bonds(); ++b)
        wrong += bond_n[b] != c.steps;
      wrong                          = dealii::Utilities::MPI::sum(wrong, comm);
      const double evaluated         = dealii::Utilities::MPI::max(double(evaluations), comm);
      const double checks            = dealii::Utilities::MPI::sum(double(ghost_checks), comm);
      const double mismatches        = dealii::Utilities::MPI::sum(double(ghost_mismatches), comm);
      const unsigned int n_ranks     = dealii::Utilities::MPI::n_mpi_processes(comm);
      std::ostringstream failures;
      if (wrong > 0)
        failures << "FAIL: " << c.type << ": " << wrong << " points or bonds whose history is not " << c.steps
                 << " commits after " << c.steps << " steps\n";
      if (c.implicit && evaluated <= c.steps + 1)
        failures << "FAIL: " << c.type << ": only " << evaluated
                 << " evaluations: the probe did not see Newton's iterations\n";
      if (mismatches > 0)
        failures << "FAIL: " << c.type << ": " << mismatches << " ghost tensor components differ from their owner's\n";
      if (n_ranks > 1 && checks == 0)
        failures << "FAIL: " << c.type << ": no bond reaches a ghost point: the tensor ghosts went unchecked\n";
      if (root)
        {
          std::cout << c.type << ": " << c.steps << " steps, " << c.steps << " commits at every point and bond, "
                    << (c.implicit ? "more evaluations than commits" : "one evaluation per step")
                    << (failures.str().empty() ? "" : " -- not so") << "\n"
                    << failures.str();
        }
      passed &= failures.str().empty();
    }
  if (root)
    std::cout << (passed ? "PASS" : "FAIL") << std::endl;
  return passed ? 0 : 1;
}
