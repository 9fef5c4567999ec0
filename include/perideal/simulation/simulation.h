#pragma once
// The simulation owns the parts and runs them: the deck read from the
// parameter file, the discretization, the force model, the coupling with
// continuum blocks (only if there is one), the conditions, the
// postprocessing, and the time integrator of Solver/Type, which sees the
// others through a SimulatorAccess.

#include <perideal/simulation/deck.h>
#include <perideal/model/state.h>
#include <perideal/solver/time_integrator.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <memory>
#include <string>

namespace perideal
{
  class Discretization;
  class ForceModel;
  class Coupling;
  class Contact;
  class Adaptivity;
  class ConditionSet;
  class Postprocess;

  class Simulation
  {
  public:
    Simulation(const std::string &parameter_file, const MPI_Comm comm);
    ~Simulation();

    /// Sets up and prints points, bonds, memory estimate and time step.
    void
    dry_run();

    /// Sets up and integrates to the final time; with @p restart (a
    /// checkpoint's directory, pd_app --restart) from the checkpoint's step.
    void
    run(const std::string &restart = "");

    /// The parts (after run() or dry_run()): what the integrator sees, and a
    /// program that drives or inspects a run.
    SimulatorAccess
    access();

  private:
    /// Mesh, points, bonds (rebalanced by bonds on several ranks), models,
    /// coupling, conditions, computes, the integrator's time step.
    void
    setup(const bool dry_run_mode);
    /// After cells converted (Adaptivity): the points, bonds and every part
    /// that depends on them again, on the same mesh, with the loads of
    /// @p time. Collective.
    void
    rebuild(const double time);
    /// The conditions' and computes' points and nodes, the constraints, and
    /// the body force and continuum handed to the model: after the points
    /// and DoFs are numbered, at the set-up and at every rebuild.
    void
    connect_conditions();
    /// The contact search of the current points (Contact's per-point data is
    /// a copy): at the set-up and at every rebuild; the count of list builds
    /// goes on. Collective.
    void
    setup_contact();
    /// Makes Solver stages' @p k-th solver the running one, from time @p start.
    void
    start_stage(const unsigned int k, const double start);

    MPI_Comm                   comm;
    std::string                restart; // run(): the checkpoint's directory, or empty
    unsigned int               stage = 0; // the running solver: 0 Solver, k Solver stages' k-th
    bool                       continues = false;
    unsigned int               base_frequency = 0, base_globals = 0; // Output's, for the stages without their own
    dealii::ConditionalOStream pcout;
    dealii::TimerOutput        timer;
    Deck                       deck;
    MechanicalState            state;
    RunRecord                  record;

    std::unique_ptr<Discretization> discretization;
    std::unique_ptr<ForceModel>     model;
    std::unique_ptr<Coupling>       coupling; // only with continuum blocks
    std::unique_ptr<Contact>        contact;  // only with Contact interactions
    std::unique_ptr<ConditionSet>   conditions;
    std::unique_ptr<Postprocess>    post;
    std::unique_ptr<Adaptivity>     adaptivity; // only with an Adaptivity section
  };
} // namespace perideal
