#pragma once
// The TimeIntegrator extension point (Solver/Type): Verlet, QuasiStatic and
// Newmark are each one file in source/solver/ registered with
// PERIDEAL_REGISTER(TimeIntegrator, Class, "Name", "documentation"). An
// integrator sees the rest of the program through SimulatorAccess (ASPECT's
// idea): the parts, the mechanical state and the run's record, and the steps
// every integrator shares (evaluate the forces, record the initial state,
// stop on a signal). Adding a fourth integrator touches no existing file but
// CMakeLists.txt.

#include <perideal/base/input.h>
#include <perideal/model/state.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace perideal
{
  struct Deck;
  struct SolverParameters;
  class Discretization;
  class ForceModel;
  class Coupling;
  class ConditionSet;
  class Postprocess;
  class ImplicitSolver;
  class CheckpointWriter;
  class CheckpointReader;
  class Adaptivity;

  /// What an integrator (and the postprocessing) may reach. Collective
  /// functions are marked so.
  class SimulatorAccess
  {
  public:
    MPI_Comm                    comm;
    dealii::ConditionalOStream &pcout;
    dealii::TimerOutput        &timer;
    const Deck                 &deck;
    Discretization             &discretization;
    ForceModel                 &model;
    Coupling                   *coupling; // nullptr without continuum blocks
    ConditionSet               &conditions;
    Postprocess                &post;
    MechanicalState            &state;
    RunRecord                  &record;
    Adaptivity                 *adaptivity; // nullptr without an Adaptivity section
    std::string                 restart; // pd_app --restart: the checkpoint's directory; empty: a fresh run
    // Solver stages: the running solver's index (0: Solver), whether it
    // continues the state of one before it (no initial conditions, no step 0,
    // the output series goes on), and whether another follows.
    unsigned int stage      = 0;
    bool         continues  = false;
    bool         last_stage = true;
    // save_parts(): the discretization's signature, hashed over every bond
    // once (it does not change after set-up), not at every checkpoint.
    mutable std::array<std::uint64_t, 4> signature{};
    mutable bool                         signature_known = false;

    /// The FE field at the virtual points, then the displacement's ghosts.
    void
    update_ghosts() const;
    /// Forces (and energy density) of the initial state, ghosts updated.
    void
    evaluate_initial_state() const;
    /// Initial energy from the globals of step 0; writes step 0 if it is an
    /// output step. Collective.
    void
    record_initial_state(const unsigned int n_steps, const double time) const;
    /// Collective: stops if a rank has received SIGTERM or SIGINT during set-up.
    void
    stop_if_interrupted_in_setup() const;
    /// Collective, after a completed @p step of a run of @p n_steps: writes
    /// it where the output writes anything (what its own output did not write
    /// already), prints the summary and throws Interrupted; @p checkpoint_note
    /// (a line, or empty) follows the error line.
    [[noreturn]] void
    stop_interrupted(const unsigned int step, const double time, const unsigned int n_steps,
                     const double loop_seconds, const std::string &checkpoint_note = "") const;
    /// Every part's state for a checkpoint (checkpoint.h): a signature of
    /// the discretization, the mechanical state, the force model, the
    /// conditions, the postprocessing, the record.
    void
    save_parts(CheckpointWriter &out) const;
    /// Reads them back, after checking collectively that this run built the
    /// same discretization, and updates the ghosts. Collective.
    void
    load_parts(CheckpointReader &in) const;
  };

  class TimeIntegrator
  {
  public:
    virtual ~TimeIntegrator() = default;

    /// Called inside subsection Solver for every registered integrator, so
    /// that errors in its keys show whichever runs.
    virtual void
    parse_parameters(ParameterHandler &)
    {}
    /// Called for the chosen one: its keys against the shared ones.
    virtual void
    check_parameters(const SolverParameters &, const bool /*has_continuum*/) const
    {}

    /// Gives the integrator the parts (once they exist).
    void
    initialize(const SimulatorAccess &simulator)
    {
      access          = std::make_unique<SimulatorAccess>(simulator);
      last_checkpoint = std::chrono::steady_clock::now();
    }

    /// After the model's set-up: the time step (record.dt) and its warnings.
    virtual void
    setup()
    {}
    /// Lines of the set-up report (the time step). Collective.
    virtual void
    report_setup() const
    {}
    /// Solver stages: at the run's set-up, before any stage runs, what
    /// would stop this one when it starts (a singular quasistatic problem),
    /// without setting it up. Collective.
    virtual void
    check_stage()
    {}
    /// --dry-run: what set-up the integrator itself does (an implicit
    /// tangent's sparsity), reported.
    virtual void
    dry_run()
    {}
    /// Integrates from the initial state to the end.
    virtual void
    run() = 0;

    /// How the summary names the loop ("time loop", "load steps").
    virtual std::string
    loop_name() const
    {
      return "time loop";
    }
    /// The summary's line on speed (bond updates per second; the tangent)
    /// after a loop of @p loop_seconds over @p steps. Collective.
    virtual void
    report_summary_speed(const double /*loop_seconds*/, const unsigned int /*steps*/) const
    {}
    /// The summary's line on the time step. Collective.
    virtual void
    report_summary_step() const
    {}
    /// Columns the integrator adds to a globals row (Newton's counts,
    /// reactions). Collective.
    virtual void
    add_globals(std::vector<std::pair<std::string, double>> &) const
    {}
    /// After run(): the steps it took (counted from its first) and the time
    /// it ended at, where a following solver starts.
    unsigned int
    steps_done() const
    {
      return finished_steps;
    }
    double
    end_time() const
    {
      return finished_time;
    }

  protected:
    /// After step @p step, accepted and written, at @p time: a checkpoint if
    /// Output/Checkpoint asks for one now (every Frequency steps, Minutes
    /// after the last, or on a signal: @p signal, known to every rank).
    /// Sets checkpoint_note. Collective.
    void
    checkpoint_step(const unsigned int step, const double time, const bool signal);
    /// With pd_app --restart: restores every part and this integrator
    /// (load_state()) from the checkpoint and returns true; false in a fresh
    /// run. Call after the initial conditions are applied, in place of the
    /// initial state's evaluation. Collective.
    bool
    restore_checkpoint();
    /// The integrator's place in the run (its step, time, and what it keeps
    /// from one step to the next), for checkpoint_step() and restore_checkpoint().
    virtual void
    save_state(CheckpointWriter &) const
    {}
    virtual void
    load_state(CheckpointReader &)
    {}

    std::unique_ptr<SimulatorAccess> access;
    unsigned int                     finished_steps = 0; // set by run(): steps_done(), end_time()
    double                           finished_time  = 0;
    // The line after the stop message when checkpoint_step() wrote a checkpoint of this step.
    std::string checkpoint_note;

  private:
    std::chrono::steady_clock::time_point last_checkpoint; // Output/Checkpoint/Minutes
  };
} // namespace perideal
