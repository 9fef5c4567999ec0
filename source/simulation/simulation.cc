// The simulation: owns the parts, sets them up in order and hands the run to
// the time integrator of Solver/Type.

#include <perideal/adaptivity/adaptivity.h>
#include <perideal/base/format.h>
#include <perideal/base/memory.h>
#include <perideal/conditions/condition_set.h>
#include <perideal/contact/contact.h>
#include <perideal/continuum/coupling.h>
#include <perideal/discretization/discretization.h>
#include <perideal/model/force_model.h>
#include <perideal/output/checkpoint.h>
#include <perideal/output/postprocess.h>
#include <perideal/simulation/simulation.h>
#include <perideal/solver/time_integrator.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  Simulation::Simulation(const std::string &parameter_file, const MPI_Comm comm)
    : comm(comm)
    , pcout(std::cout, Utilities::MPI::this_mpi_process(comm) == 0)
    , timer(pcout, TimerOutput::never, TimerOutput::wall_times)
  {
    // The libraries are loaded and initialised by now: what the scene adds
    // to this is its own memory.
    record.startup_memory = resident_memory_bytes();
    read_deck(parameter_file, deck);
  }

  Simulation::~Simulation() = default;

  SimulatorAccess
  Simulation::access()
  {
    return SimulatorAccess{comm, pcout, timer, deck, *discretization, *model, coupling.get(), *conditions, *post, state, record, adaptivity.get(), restart, stage, continues,
                           stage == deck.stages.size()};
  }

  void
  Simulation::setup(const bool dry_run_mode)
  {
    const auto start = std::chrono::steady_clock::now();
    discretization   = std::make_unique<Discretization>(deck, comm, pcout, timer, dry_run_mode);
    discretization->setup();
    record.warnings.insert(record.warnings.end(), discretization->setup_warnings.begin(),
                           discretization->setup_warnings.end());
    model = std::make_unique<ForceModel>(*discretization, state, record, comm, timer);
    if (!deck.temperature.function.empty())
      model->set_temperature(std::make_unique<Expression>(deck.temperature.function, "Temperature/Function"),
                             deck.temperature.reference);
    if (deck.adaptivity.active())
      model->keep_point_steps(); // a conversion computes only the steps that changed
    model->setup();
    if (deck.has_continuum)
      {
        TimerOutput::Scope t(timer, "setup: continuum");
        coupling = std::make_unique<Coupling>();
        coupling->setup(*discretization, comm);
      }
    state.number_dofs(*discretization, coupling ? &coupling->continuum : nullptr);
    conditions = std::make_unique<ConditionSet>(deck.conditions, *discretization, state, record, comm);
    post = std::make_unique<Postprocess>(deck, *discretization, *model, *conditions, state, record, comm, pcout, timer);
    connect_conditions();
    if (deck.contact.active())
      {
        TimerOutput::Scope t(timer, "setup: contact");
        setup_contact();
        record.warnings.insert(record.warnings.end(), contact->setup_warnings.begin(), contact->setup_warnings.end());
      }

    record.dt_stable = model->stable_time_step();
    if (deck.adaptivity.active())
      {
        adaptivity = std::make_unique<Adaptivity>(deck.adaptivity, *discretization, *model, *coupling, *post, state,
                                                  record, comm, pcout, timer, [this](const double time) { rebuild(time); });
        adaptivity->use_integrator(deck.solver.type == "Verlet", deck.solver.type != "QuasiStatic");
      }
    // The stages still to come are checked now, not when they start (after
    // the ones before them have run and written their output).
    for (unsigned int k = stage; k < deck.stages.size(); ++k)
      {
        deck.stages[k].integrator->initialize(access());
        try
          {
            deck.stages[k].integrator->check_stage();
          }
        catch (const ExceptionBase &e)
          {
            std::ostringstream message;
            e.print_info(message);
            AssertThrow(false, ExcMessage("Solver stages/" + deck.stages[k].name + ": " +
                                          Utilities::trim(message.str())));
          }
      }
    deck.integrator->initialize(access());
    deck.integrator->setup();
    record.setup_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  void
  Simulation::rebuild(const double time)
  {
    const std::size_t known = record.warnings.size();
    discretization->rebuild_points_and_bonds();
    record.warnings.insert(record.warnings.end(), discretization->setup_warnings.begin(),
                           discretization->setup_warnings.end());
    {
      TimerOutput::Scope t(timer, "rebuild: model");
      model->setup();
    }
    {
      TimerOutput::Scope t(timer, "rebuild: continuum");
      coupling->setup(*discretization, comm);
    }
    {
      TimerOutput::Scope t(timer, "rebuild: conditions and computes");
      state.number_dofs(*discretization, &coupling->continuum);
      connect_conditions();
      conditions->evaluate_loads(time);
    }
    if (contact)
      {
        TimerOutput::Scope t(timer, "rebuild: contact");
        setup_contact();
      }
    {
      TimerOutput::Scope t(timer, "rebuild: stable step");
      record.dt_stable = model->stable_time_step();
    }
    // The warnings the set-up gave once are not repeated.
    const std::vector<std::string> found(record.warnings.begin() + known, record.warnings.end());
    record.warnings.resize(known);
    for (const auto &w : found)
      if (std::find(record.warnings.begin(), record.warnings.end(), w) == record.warnings.end())
        record.warnings.push_back(w);
  }

  void
  Simulation::setup_contact()
  {
    const unsigned int builds = contact ? contact->builds : 0;
    contact = std::make_unique<Contact>(deck.contact, model->blocks, discretization->cloud, discretization->bonds,
                                        comm, timer);
    contact->setup(state.mass_density, discretization->point_spacing());
    contact->builds = builds;
    model->attach_contact(contact.get());
  }

  void
  Simulation::connect_conditions()
  {
    conditions->setup(coupling.get());
    post->setup(coupling.get());
    conditions->setup_constraints();
    model->rigid.check_constraints(*conditions);
    model->attach(conditions->body_force, coupling.get());
  }

  void
  Simulation::dry_run()
  {
    setup(true);
    access().stop_if_interrupted_in_setup();
    deck.output.initialize(comm); // the checks of the output and checkpoint directories
    post->print_setup_report();
    if (adaptivity)
      adaptivity->report_setup();
    const AvailableMemory available = available_memory(comm);
    if (std::isfinite(available.bytes_per_rank))
      pcout << "  memory available:  " << mib(available.bytes_per_rank) << " per rank (" << available.limited_by
            << ")\n";
    deck.integrator->dry_run();
    pcout << "Dry run: set-up done, no time step taken." << std::endl;
  }

  void
  Simulation::run(const std::string &restart_directory)
  {
    // A restart continues the solver (Solver stages) its checkpoint was written in.
    const CheckpointStage from = restart_directory.empty() ? CheckpointStage() : checkpoint_stage(restart_directory, comm);
    AssertThrow(from.stage <= deck.stages.size(),
                ExcMessage("--restart '" + restart_directory + "': the checkpoint was written by the solver of Solver "
                           "stages number " + std::to_string(from.stage) + ", this parameter file has " +
                           std::to_string(deck.stages.size())));
    restart        = restart_directory;
    base_frequency = deck.output.frequency;
    base_globals   = deck.output.globals_frequency;
    if (from.stage > 0)
      start_stage(from.stage, from.start);
    setup(false);
    access().stop_if_interrupted_in_setup();
    post->print_setup_report();
    if (adaptivity)
      adaptivity->report_setup();
    deck.integrator->run();
    while (stage < deck.stages.size())
      {
        post->step_offset += deck.integrator->steps_done();
        const double end = deck.integrator->end_time();
        start_stage(stage + 1, end);
        restart.clear();
        const SolverStage &s = deck.stages[stage - 1];
        pcout << "\nSolver stages/" << s.name << ": " << deck.solver.type << " from t = " << end << " (step "
              << post->step_offset << ")" << std::endl;
        deck.integrator->initialize(access());
        deck.integrator->setup();
        deck.integrator->run();
      }
  }

  void
  Simulation::start_stage(const unsigned int k, const double start)
  {
    SolverStage &s = deck.stages[k - 1];
    AssertThrow(s.solver.requested_steps > 0 || s.solver.final_time > start,
                ExcMessage("Solver stages/" + s.name + "/Final time (" + sci(s.solver.final_time, 6) +
                           ") must be after the end of the solver before it (t = " + sci(start, 6) +
                           "), or set Number of steps"));
    deck.solver              = s.solver;
    deck.solver.initial_time = start;
    deck.integrator          = std::move(s.integrator);
    deck.output.frequency         = s.output_frequency >= 0 ? s.output_frequency : base_frequency;
    deck.output.globals_frequency = s.globals_frequency >= 0 ? s.globals_frequency : base_globals;
    stage                    = k;
    continues                = true;
  }
} // namespace perideal
