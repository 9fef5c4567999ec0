// The steps every integrator shares (time_integrator.h).

#include <perideal/base/format.h>
#include <perideal/base/interrupt.h>
#include <perideal/continuum/coupling.h>
#include <perideal/model/force_model.h>
#include <perideal/simulation/deck.h>
#include <perideal/output/postprocess.h>
#include <perideal/solver/time_integrator.h>

#include <deal.II/base/mpi.h>

#include <cmath>
#include <iostream>

namespace perideal
{
  using namespace dealii;

  void
  SimulatorAccess::update_ghosts() const
  {
    if (coupling)
      coupling->update_virtual_points(state.displacement);
    state.displacement.update_ghost_values();
  }

  void
  SimulatorAccess::evaluate_initial_state() const
  {
    // Initial conditions are set point by point; a rigid body starts with the
    // rigid motion of their momentum and angular momentum.
    model.rigid.unify_velocities(state.displacement.begin(), state.velocity.begin());
    update_ghosts();
    model.set_time(deck.solver.initial_time, 0);
    model.compute_forces(true);
  }

  void
  SimulatorAccess::record_initial_state(const unsigned int n_steps, const double time) const
  {
    const auto row        = post.global_quantities(0, time);
    record.initial_energy = row[2].second + row[3].second + record.last_contact_energy;
    // Far from t = 0 a double cannot hold t + dt: time would stall (t + dt
    // == t) or advance in steps other than dt, silently. 1e-10 leaves each
    // step's time exact to 1e-6 of dt.
    const double dt     = record.dt;
    const double latest = std::max(std::abs(time), std::abs(time + n_steps * dt));
    AssertThrow(dt > 1e-10 * latest,
                ExcMessage("Solver/Initial time: at t = " + sci(latest, 6) + " the time step " + sci(dt, 6) +
                           " is below the resolution of the time (1e-10 of t): t + dt would not be t plus the "
                           "step. Count the time from 0 (Initial time = 0, Final time = the duration)"));
    if (post.output.is_output_step(0, n_steps))
      post.write_output(0, time, post.output.is_globals_step(0, n_steps), post.output.is_field_step(0, n_steps));
  }

  void
  SimulatorAccess::stop_if_interrupted_in_setup() const
  {
    const int signal = interrupt_signal(comm);
    if (signal != 0)
      throw Interrupted(signal, "interrupted by " + signal_name(signal) +
                                  " during set-up, before the first step: nothing written");
  }

  void
  SimulatorAccess::stop_interrupted(const unsigned int step, const double time, const unsigned int n_steps,
                                    const double loop_seconds) const
  {
    const int           signal = interrupt_signal(comm);
    const OutputWriter &output = post.output;
    // The state at the stop goes to disk as a run's last step would: what
    // the step's own output (with @p n_steps) did not write yet.
    const bool wrote       = output.is_output_step(step, n_steps);
    const bool add_globals = output.is_globals_step(step, step) && !output.is_globals_step(step, n_steps);
    const bool add_fields  = output.is_field_step(step, step) && !output.is_field_step(step, n_steps);
    if (!wrote)
      model.compute_forces(true); // the energies (explicit steps compute them at output steps only)
    if (add_globals || add_fields)
      post.write_output(step, time, add_globals, add_fields);
    else if (!wrote)
      post.global_quantities(step, time); // the summary's energy balance
    const std::string message = "interrupted by " + signal_name(signal) + " at step " + std::to_string(step) +
                                " (t = " + sci(time, 6) + "): " +
                                (output.is_output_step(step, step) ?
                                   "the output holds steps up to " + std::to_string(step) :
                                   std::string("nothing written (Output/Frequency = 0)"));
    // Said before the summary: mpirun, stopping the job, may drop what a
    // rank writes last.
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      std::cerr << "Error: " << message << std::endl;
    post.print_summary(loop_seconds, step);
    throw Interrupted(signal, message, /*reported=*/true);
  }
} // namespace perideal
