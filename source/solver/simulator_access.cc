// The steps every integrator shares (time_integrator.h).

#include <perideal/adaptivity/adaptivity.h>
#include <perideal/base/format.h>
#include <perideal/base/interrupt.h>
#include <perideal/continuum/coupling.h>
#include <perideal/model/force_model.h>
#include <perideal/simulation/deck.h>
#include <perideal/conditions/condition_set.h>
#include <perideal/output/checkpoint.h>
#include <perideal/output/postprocess.h>
#include <perideal/solver/time_integrator.h>

#include <deal.II/base/mpi.h>

#include <array>
#include <chrono>
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
    post.output.create_files(comm); // every check of the set-up has passed: now write
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
                                    const double loop_seconds, const std::string &checkpoint_note) const
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
    const std::string message = "interrupted by " + signal_name(signal) + " at step " +
                                std::to_string(step + post.step_offset) +
                                " (t = " + sci(time, 6) + "): " +
                                (output.is_output_step(step, step) ?
                                   "the output holds steps up to " + std::to_string(step + post.step_offset) :
                                   std::string("nothing written (Output/Frequency = 0)"));
    // Said before the summary: mpirun, stopping the job, may drop what a
    // rank writes last.
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      write_to_stderr("Error: " + message + "\n" + checkpoint_note);
    post.print_summary(loop_seconds, step);
    throw Interrupted(signal, message, /*reported=*/true);
  }

  namespace
  {
    /// FNV-1a over @p size bytes.
    std::uint64_t
    fnv1a(const void *data, const std::size_t size, std::uint64_t h = 14695981039346656037ull)
    {
      const unsigned char *p = static_cast<const unsigned char *>(data);
      for (std::size_t i = 0; i < size; ++i)
        h = (h ^ p[i]) * 1099511628211ull;
      return h;
    }

    /// What identifies this rank's share of the discretization: its points,
    /// bonds and DoFs, and a hash of the points' reference positions, global
    /// numbers and families.
    std::array<std::uint64_t, 4>
    compute_signature(const SimulatorAccess &access)
    {
      const PointCloud &cloud = access.discretization.cloud;
      const Bonds      &bonds = access.discretization.bonds;
      std::uint64_t     h     = fnv1a(cloud.X.data(), cloud.X.size() * sizeof(double));
      h = fnv1a(cloud.gid.data(), cloud.gid.size() * sizeof(cloud.gid[0]), h);
      h = fnv1a(bonds.offsets.data(), bonds.offsets.size() * sizeof(bonds.offsets[0]), h);
      h = fnv1a(bonds.neighbor.data(), bonds.neighbor.size() * sizeof(bonds.neighbor[0]), h);
      return {{cloud.n_owned(), bonds.n_bonds(), access.state.size(), h}};
    }
  } // namespace

  void
  SimulatorAccess::save_parts(CheckpointWriter &out) const
  {
    // The converted cells first: a restart makes their points and bonds
    // before it compares the discretization and reads the state.
    if (adaptivity && adaptivity->changes_mesh())
      {
        const Adaptivity::MeshHistory &history = adaptivity->mesh_history();
        out.section("mesh history");
        out.put(history.events);
        out.put(history.split);
        out.put(history.weighed);
        out.put(history.weights);
      }
    if (adaptivity)
      {
        out.section("converted cells");
        out.put(discretization.converted);
      }
    out.section("discretization");
    if (!signature_known)
      signature = compute_signature(*this);
    signature_known = true;
    out.put(signature);
    state.save(out);
    model.save(out);
    conditions.save(out);
    post.save(out);
    record.save(out);
  }

  void
  SimulatorAccess::load_parts(CheckpointReader &in) const
  {
    if (adaptivity && adaptivity->changes_mesh())
      {
        // The mesh as the conversions refined and partitioned it, before its
        // cells are counted.
        Adaptivity::MeshHistory history;
        in.section("mesh history");
        in.get(history.events);
        in.get(history.split);
        in.get(history.weighed);
        in.get(history.weights);
        adaptivity->replay(history);
      }
    if (adaptivity)
      {
        in.section("converted cells");
        const auto converted = in.get<std::vector<std::uint8_t>>();
        in.expect(converted.empty() || converted.size() == discretization.triangulation.n_active_cells(),
                  "the converted cells are flagged over " + std::to_string(converted.size()) +
                    " cells on this rank, the mesh has " +
                    std::to_string(discretization.triangulation.n_active_cells()));
        adaptivity->restore_converted(converted);
      }
    in.section("discretization");
    const auto  there = in.get<std::array<std::uint64_t, 4>>();
    const auto  here  = compute_signature(*this);
    std::string problem;
    if (there != here)
      problem = "rank " + std::to_string(Utilities::MPI::this_mpi_process(comm)) + " has " +
                std::to_string(here[0]) + " points, " + std::to_string(here[1]) + " bonds and " +
                std::to_string(here[2]) + " degrees of freedom here, " + std::to_string(there[0]) + ", " +
                std::to_string(there[1]) + " and " + std::to_string(there[2]) + " in the checkpoint" +
                (there[0] == here[0] && there[1] == here[1] && there[2] == here[2] ?
                   std::string(", and the points' positions or families differ") :
                   std::string());
    for (const std::string &p : Utilities::MPI::all_gather(comm, problem))
      AssertThrow(p.empty(),
                  ExcMessage("--restart '" + restart + "': the checkpoint holds another discretization: " + p +
                             ". The parameters are the same, so a file they read has changed (a Gmsh mesh?)"));
    state.load(in);
    update_ghosts();
    model.load(in);
    conditions.load(in);
    post.load(in);
    record.load(in);
  }

  // ------------------------------------------------ TimeIntegrator

  void
  TimeIntegrator::checkpoint_step(const unsigned int step, const double time, const bool signal)
  {
    const CheckpointParameters &parameters = access->deck.output.checkpoint;
    const MPI_Comm              comm       = access->comm;
    checkpoint_note.clear();
    // Counted by the run's step (Solver stages number on), not the stage's.
    const unsigned int run_step = step + access->post.step_offset;
    bool due = (parameters.frequency > 0 && run_step % parameters.frequency == 0) || (signal && parameters.on_signal);
    if (parameters.minutes > 0 && !due)
      {
        // Rank 0's clock decides, for all.
        const int late = std::chrono::duration<double>(std::chrono::steady_clock::now() - last_checkpoint).count() >=
                         60 * parameters.minutes;
        due = Utilities::MPI::broadcast(comm, late, 0) != 0;
      }
    if (!due)
      return;
    const auto now = std::chrono::steady_clock::now();
    double bytes = 0;
    {
      TimerOutput::Scope t(access->timer, "checkpoint");
      CheckpointWriter   out(parameters.directory, comm);
      out.section("PeriDeal checkpoint");
      access->save_parts(out);
      out.section("integrator");
      save_state(out);
      bytes = out.finish(access->deck.output.parameter_text(), run_step, time, access->stage,
                         access->deck.solver.initial_time);
    }
    last_checkpoint = std::chrono::steady_clock::now();
    access->pcout << "  checkpoint of step " << run_step << " (t = " << sci(time, 6) << "): " << parameters.directory
                  << ", " << (bytes >= 1048576 ? mib(bytes) : sci(bytes / 1024, 3) + " KiB") << " in " << sci(std::chrono::duration<double>(last_checkpoint - now).count(), 3)
                  << " s" << std::endl;
    const unsigned int ranks = Utilities::MPI::n_mpi_processes(comm);
    checkpoint_note = "A checkpoint of step " + std::to_string(run_step) + " is in '" + parameters.directory +
                      "': continue with pd_app --restart " + parameters.directory + " and the same parameter file" +
                      (ranks > 1 ? " on " + std::to_string(ranks) + " ranks" : std::string()) + ".\n";
  }

  bool
  TimeIntegrator::restore_checkpoint()
  {
    if (access->restart.empty())
      return false;
    TimerOutput::Scope t(access->timer, "checkpoint");
    auto [in, header] = read_checkpoint(access->restart, access->deck.output.parameter_text(), access->comm);
    in.section("PeriDeal checkpoint");
    access->load_parts(in);
    in.section("integrator");
    load_state(in);
    in.expect(in.at_end(), "bytes are left after the integrator's state");
    access->pcout << "Restarted from '" << access->restart << "': step " << header.step << ", t = "
                  << sci(header.time, 6) << std::endl;
    return true;
  }
} // namespace perideal
