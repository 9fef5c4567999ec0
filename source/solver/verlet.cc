// Explicit velocity-Verlet with lumped mass (Solver/Type = Verlet):
//   v += dt/2 f/rho;  u += dt v;  prescribed entries;  f = f(u);  v += dt/2 f/rho
// over every DoF of the mechanical state, PD point entries and FE DoFs (with
// their lumped mass) alike. The step is a safety factor times the smallest
// stable estimate (or fixed), shortened while a point with intact bonds moves
// more than a fraction of the point spacing per step. The work of supports
// and loads is summed per step (trapezoid rule), so the energy balance of the
// summary closes; a run whose kinetic energy grows past a limit, or turns
// non-finite, stops naming the point and the likely cause.

#include <perideal/adaptivity/adaptivity.h>
#include <perideal/base/best_point.h>
#include <perideal/base/format.h>
#include <perideal/base/interrupt.h>
#include <perideal/output/checkpoint.h>
#include <perideal/conditions/condition_set.h>
#include <perideal/contact/contact.h>
#include <perideal/model/force_model.h>
#include <perideal/output/postprocess.h>
#include <perideal/simulation/deck.h>
#include <perideal/solver/stability_guard.h>
#include <perideal/solver/time_integrator.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <limits>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    // The automatic Verlet step keeps every point with intact bonds within
    // this fraction of the point spacing per step. A point that crosses a
    // large part of the spacing in one step outruns its neighbours' forces
    // and energy is made: two blocks meeting at Mach 2 (tests/stability/
    // impact.prm) gain 4.6% of their kinetic energy at 1.55 spacings per
    // step (the stable elastic step), 0.98% at 0.77, 0.39% at 0.39, 0.089%
    // at 0.19: about 0.02 (|v| dt/h)^2. LAMMPS' fix dt/reset limits the
    // same motion per step.
    constexpr double max_spacing_fraction = 0.2;
  } // namespace

  namespace
  {
    class Verlet : public TimeIntegrator
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Verlet");
        prm.declare_entry("Fixed dt", "0", Patterns::Double(0),
                          "Time step; 0: Safety factor times the smallest stable estimate over all points, "
                          "shortened in a step that starts with a point with intact bonds faster than 0.2 "
                          "point spacings per step (a faster one outruns its neighbours' forces and makes "
                          "energy; a fixed step that allows it is warned about).");
        prm.declare_entry("Safety factor", "0.8", Patterns::Double(0, 1),
                          "Fraction of the stable time step used when Fixed dt is 0.");
        prm.leave_subsection();
      }

      void
      parse_parameters(ParameterHandler &prm) override
      {
        prm.enter_subsection("Verlet");
        fixed_dt      = prm.get_double("Fixed dt");
        safety_factor = prm.get_double("Safety factor");
        prm.leave_subsection();
        AssertThrow(fixed_dt > 0 || safety_factor > 0,
                    ExcMessage("Solver/Verlet/Safety factor must be positive when Fixed dt is 0"));
      }

      void
      setup() override
      {
        RunRecord &record = access->record;
        AssertThrow(fixed_dt > 0 || record.dt_stable < std::numeric_limits<double>::max(),
                    ExcMessage("Solver/Verlet/Fixed dt is 0 (the automatic step), but no block gives a stable time "
                               "step: every block is rigid (or has no bonds) and no contact stiffness limits it: "
                               "set Solver/Verlet/Fixed dt"));
        record.dt = fixed_dt > 0 ? fixed_dt : safety_factor * record.dt_stable;
        if (fixed_dt > record.dt_stable)
          record.warnings.push_back("Fixed dt " + sci(fixed_dt) + " exceeds the stable estimate " +
                                    sci(record.dt_stable) + " (" + sci(fixed_dt / record.dt_stable, 3) +
                                    " times): the run may become unstable");
      }

      void
      report_setup() const override
      {
        access->pcout << "  stable time step:  " << sci(access->record.dt_stable, 6)
                      << " (smallest over all points)\n"
                      << "  time step:         " << sci(access->record.dt, 6)
                      << (fixed_dt > 0 ? " (fixed)" : " (safety factor " + sci(safety_factor, 3) + ")") << "\n";
      }

      void
      run() override
      {
        do_initial_timestep();
        // A checkpoint of a stage's last step continues with the next stage.
        if (!at_end())
          while (!do_timestep())
            ;
        finish();
      }

      void
      report_summary_speed(const double loop_seconds, const unsigned int steps) const override
      {
        const double       bonds   = Utilities::MPI::sum(double(access->discretization.bonds.n_bonds()), access->comm);
        const double       updates = loop_seconds > 0 ? bonds * steps / loop_seconds : 0;
        const unsigned int ranks   = Utilities::MPI::n_mpi_processes(access->comm);
        access->pcout << "  bond updates per second: " << sci(updates / 1e6, 4) << " M ("
                      << sci(updates / 1e6 / ranks, 4) << " M per rank)\n";
      }

      void
      report_summary_step() const override
      {
        const RunRecord &record = access->record;
        access->pcout << "  stable time step:       " << sci(record.dt_stable, 6) << ", used " << sci(record.dt, 6);
        if (record.shortened_steps > 0)
          access->pcout << "; " << record.shortened_steps << " steps shortened to keep max |v| dt <= "
                        << sci(max_spacing_fraction, 2) << " point spacings, the shortest " << sci(record.shortest_dt, 6);
        access->pcout << "\n";
      }

    private:
      /// The step count, the initial state (written at step 0), and what the
      /// steps keep: inverse densities and masses, the constrained entries.
      void
      do_initial_timestep();
      /// One step; true after the last one.
      bool
      do_timestep();
      /// The final energies and the summary.
      void
      finish();
      /// After cells converted (Adaptivity): the per-DoF arrays, the
      /// supports' and loads' start values in the new numbering, and the
      /// stable step of the new model.
      void
      take_conversion();
      /// Stops, after writing the last good state, if the step made the state
      /// non-finite or the kinetic energy grew past the limit. Collective.
      void
      check_growth(const double ke, const double new_time);
      /// The progress line every 10% or 30 s.
      void
      report_progress(const bool last);
      void
      save_state(CheckpointWriter &out) const override;
      void
      load_state(CheckpointReader &in) override;

      /// The solver's steps are done (a checkpoint of its last step).
      bool
      at_end() const
      {
        return counted ? step >= n_steps : time >= access->deck.solver.final_time;
      }

      double fixed_dt = 0, safety_factor = 0.8;

      // The run: its steps, its clock, and where it stands.
      unsigned int n_steps = 0, step = 0;
      bool         counted  = true; // n_steps steps; else up to Final time
      bool         adaptive = true; // the automatic step (shortened for fast points)
      double       time = 0, dt_elastic = 0, spacing = 0, speed = 0;
      // Steps of equal length count their time from here: the start, or the
      // last conversion (which may change the stable step).
      double       base_time = 0;
      unsigned int base_step = 0;
      bool         fast_warned = false, contact_warned = false, unstable_warned = false;
      std::chrono::steady_clock::time_point start, last_print;
      double                                last_percent = 0;

      // What the steps keep, per DoF (MechanicalState's numbering).
      std::vector<double>        u_previous, v_previous, load_previous;
      ForceModel::DamageSnapshot damage_before; // the bonds' damage before a step's damage pass
    };

    void
    Verlet::do_initial_timestep()
    {
      const SolverParameters &solver     = access->deck.solver;
      RunRecord              &record     = access->record;
      ConditionSet           &conditions = access->conditions;
      MechanicalState        &state      = access->state;
      const MPI_Comm          comm       = access->comm;

      if (access->adaptivity)
        access->adaptivity->use_integrator(true, true);
      n_steps = solver.requested_steps;
      if (n_steps == 0)
        {
          // Counted in double first: steps are numbered in 32 bits, and a
          // count that wrapped would silently replace dt by another step.
          const double steps = std::ceil((solver.final_time - solver.initial_time) / record.dt - 1e-9);
          AssertThrow(steps <= double(std::numeric_limits<unsigned int>::max()),
                      ExcMessage("Solver/Final time: (Final time - Initial time) / dt = (" + sci(solver.final_time, 6) +
                                 " - " + sci(solver.initial_time, 6) + ") / " + sci(record.dt, 6) +
                                 (fixed_dt > 0 ? std::string(" (Solver/Verlet/Fixed dt)") :
                                                 " (the stable time step x Solver/Verlet/Safety factor " +
                                                   sci(safety_factor, 3) + ")") +
                                 " is " + sci(steps, 4) + " steps, more than the " +
                                 std::to_string(std::numeric_limits<unsigned int>::max()) +
                                 " a run can number: shorten the run" +
                                 (fixed_dt > 0 ? std::string(" or take a larger Fixed dt") :
                                                 std::string(" or use coarser cells (a larger stable step)"))));
          n_steps   = std::max(1u, static_cast<unsigned int>(steps));
          record.dt = (solver.final_time - solver.initial_time) / n_steps;
        }
      access->stop_if_interrupted_in_setup();
      const bool restart = !access->restart.empty(), continues = access->continues;
      if (restart || !continues)
        access->post.output.initialize(comm);
      // Bonds break in the force evaluations (an implicit solver before may have stopped that).
      access->model.breaking_allowed = true;
      if (!continues)
        conditions.apply_initial_conditions(solver.initial_time);
      if (!restart)
        {
          // A stage that continues starts from the forces the one before left.
          if (!continues)
            {
              access->evaluate_initial_state();
              access->record_initial_state(n_steps, solver.initial_time);
            }
          for (unsigned int c = 0; c < conditions.constraints.size(); ++c)
            conditions.constraint_force[c] = state.f(conditions.constraints[c].dof);
        }
      u_previous.resize(state.size());
      v_previous.resize(state.size());
      // The loads at the start of a step (constant loads: the same as at its end).
      load_previous.clear();
      if (conditions.has_loads())
        for (unsigned int k = 0; k < state.size(); ++k)
          load_previous.push_back(conditions.load(k));

      access->pcout << "Time integration: " << n_steps << " steps of " << sci(record.dt, 6)
                    << " from t = " << solver.initial_time
                    << (fixed_dt == 0 ? " (shorter while a point moves more than " + sci(max_spacing_fraction, 2) +
                                          " point spacings per step)" :
                                        "")
                    << std::endl;
      start        = std::chrono::steady_clock::now();
      last_print   = start;
      last_percent = 0;
      step         = 0;
      time         = solver.initial_time;
      base_time    = time;
      base_step    = 0;
      // The automatic step also keeps max |v| dt <= max_spacing_fraction h
      // (see there); a fixed one is only warned about.
      adaptive    = fixed_dt == 0;
      counted     = solver.requested_steps > 0 || !adaptive;
      dt_elastic  = record.dt;
      spacing     = access->discretization.point_spacing();
      speed       = access->model.fastest_bonded_speed();
      fast_warned = false;
      if (restart)
        {
          // The state, the record and where the loop stood; the loads of
          // the checkpoint's time are the next step's start.
          restore_checkpoint();
          AssertThrow(!access->last_stage || !at_end(),
                      ExcMessage("--restart '" + access->restart + "': the checkpoint is of the run's last step (" +
                                 std::to_string(step) + ", t = " + sci(time, 6) + "): nothing is left to run"));
          access->post.output.create_files(comm); // the checkpoint is accepted: now write
          // Cells converted before the checkpoint: the arrays of the new numbering.
          u_previous.resize(state.size());
          v_previous.resize(state.size());
          spacing = access->discretization.point_spacing();
          load_previous.clear();
          if (conditions.has_loads())
            {
              conditions.evaluate_loads(time);
              for (unsigned int k = 0; k < state.size(); ++k)
                load_previous.push_back(conditions.load(k));
            }
        }
    }

    void
    Verlet::save_state(CheckpointWriter &out) const
    {
      out.section("Verlet");
      out.put(n_steps);
      out.put(step);
      out.put(counted);
      out.put(adaptive);
      out.put(time);
      out.put(dt_elastic);
      out.put(speed);
      out.put(fast_warned);
      out.put(contact_warned);
      out.put(last_percent);
      out.put(base_time);
      out.put(base_step);
    }

    void
    Verlet::load_state(CheckpointReader &in)
    {
      in.section("Verlet");
      const unsigned int steps = in.get<unsigned int>();
      in.expect(steps == n_steps, "the run has " + std::to_string(n_steps) + " steps, the checkpoint's " +
                                    std::to_string(steps));
      in.get(step);
      in.get(counted);
      in.get(adaptive);
      in.get(time);
      in.get(dt_elastic);
      in.get(speed);
      in.get(fast_warned);
      in.get(contact_warned);
      in.get(last_percent);
      in.get(base_time);
      in.get(base_step);
    }

    bool
    Verlet::do_timestep()
    {
      const SolverParameters &solver     = access->deck.solver;
      RunRecord              &record     = access->record;
      ConditionSet           &conditions = access->conditions;
      MechanicalState        &state      = access->state;
      ForceModel             &model      = access->model;
      Postprocess            &post       = access->post;
      const MPI_Comm          comm       = access->comm;
      TimerOutput            &timer      = access->timer;
      double                 &dt         = record.dt;

      ++step;
      if (adaptive && speed * dt_elastic > max_spacing_fraction * spacing)
        {
          dt = max_spacing_fraction * spacing / speed;
          ++record.shortened_steps;
          record.shortest_dt = std::min(record.shortest_dt, dt);
        }
      else
        dt = dt_elastic;
      // With Number of steps or a fixed step: n_steps steps; else up to
      // Final time, the last step shortened to land on it.
      const bool last = counted ? step == n_steps : time + dt * (1 + 1e-9) >= solver.final_time;
      if (last && !counted)
        dt = solver.final_time - time;
      const double new_time = last && !counted           ? solver.final_time :
                              record.shortened_steps > 0 ? time + dt :
                                                           base_time + (step - base_step) * dt;
      const unsigned int steps_now = counted ? n_steps : last ? step : 0; // for the output steps
      {
        TimerOutput::Scope t(timer, "time integration");
        // Half kick and drift; the force already holds the body force.
        state.for_each([&](const MechanicalState::DoF &d) {
          u_previous[d.number] = d.u;
          v_previous[d.number] = d.v;
          d.v += 0.5 * dt * d.f * d.inverse_density;
          d.u += dt * d.v;
        });
        conditions.apply_prescribed(new_time, dt);
        model.set_time(new_time, dt);
        state.distribute_displacement();
        if (conditions.loads_depend_on_time)
          {
            // The work of a load over the step is the trapezoid of its two ends.
            for (unsigned int k = 0; k < load_previous.size(); ++k)
              load_previous[k] = conditions.load(k);
            conditions.evaluate_loads(new_time);
          }
      }
      {
        TimerOutput::Scope t(timer, "ghost exchange");
        access->update_ghosts();
      }
      const bool output_step = post.output.is_output_step(step, steps_now);
      if (solver.track_dissipation && !model.broken.empty())
        model.save_damage(damage_before);
      const std::size_t damage_so_far = model.damage_updates;
      model.compute_forces(output_step);

      double ke = 0, work = 0;
      {
        TimerOutput::Scope t(timer, "time integration");
        state.for_each([&](const MechanicalState::DoF &d) { d.v += 0.5 * dt * d.f * d.inverse_density; });
        // Prescribed velocities stay as prescribed. The work of a support:
        // the change of kinetic energy of its DoF minus the work of the
        // internal force on it.
        for (unsigned int c = 0; c < conditions.constraints.size(); ++c)
          {
            const unsigned int k = conditions.constraints[c].dof;
            if (state.is_hanging(k)) // follows its masters
              continue;
            const BoundaryCondition &bc = conditions.conditions[conditions.constraints[c].condition];
            double                  &vk = state.v(k);
            const double             du = state.u(k) - u_previous[k], f = state.f(k);
            if (bc.type == BoundaryCondition::Type::prescribed_velocity)
              vk = bc.value->value(state.position(k), new_time, state.hash(k));
            else
              vk = du / dt;
            work += 0.5 * state.mass(k) * (vk * vk - v_previous[k] * v_previous[k]) -
                    0.5 * (conditions.constraint_force[c] + f) * state.measure(k) * du;
            conditions.constraint_force[c] = f;
          }
        const std::vector<std::uint8_t> &prescribed = conditions.prescribed;
        state.for_each([&](const MechanicalState::DoF &d) { ke += 0.5 * d.density * d.measure * d.v * d.v; });
        if (!load_previous.empty())
          state.for_each([&](const MechanicalState::DoF &d) {
            if (!prescribed[d.number])
              work += 0.5 * (conditions.load(d.number) + load_previous[d.number]) * d.measure * (d.u - u_previous[d.number]);
          });
      }
      if (conditions.loads_depend_on_time)
        for (const double b : conditions.body_force)
          if (!std::isfinite(b))
            conditions.bad_condition = conditions.conditions.size(); // reported below by a collective search
      // The last entry: ranks that have received SIGTERM or SIGINT (the step
      // is finished, written if an output step, then the run stops).
      const double friction_power = model.contact_forces() ? model.contact_forces()->friction_power : 0.0;
      double sums[6] = {ke, work, double(conditions.bad_condition), double(model.damage_updates - damage_so_far),
                        local_interrupt_signal() != 0 ? 1.0 : 0.0, friction_power};
      {
        TimerOutput::Scope t(timer, "global sums");
        Utilities::MPI::sum(ArrayView<const double>(sums, 6), comm, ArrayView<double>(sums, 6));
      }
      ke = sums[0];
      // Friction's power at the step's evaluation (velocities of mid-step) over the step.
      record.contact_dissipation -= sums[5] * dt;
      record.external_work += sums[1];
      if (solver.track_dissipation && sums[3] > 0)
        {
          // Leaves the same forces (same state and bonds) for the next kick.
          TimerOutput::Scope t(timer, "dissipation");
          record.dissipated_energy += model.released_energy(damage_before);
        }
      // The step's one evaluation is the accepted one.
      model.commit_step();
      if (sums[2] > 0)
        {
          // Name the condition (collective), then stop.
          conditions.check_condition_values(conditions.first_nonfinite_condition(new_time), new_time);
          AssertThrow(false, ExcMessage("a boundary condition gave a non-finite value at t = " + sci(new_time, 6)));
        }
      check_growth(ke, new_time);

      time = new_time;
      if (output_step)
        post.write_output(step, time, post.output.is_globals_step(step, steps_now),
                          post.output.is_field_step(step, steps_now));
      if (access->adaptivity && !last && access->adaptivity->due(step) && access->adaptivity->check(step, time, dt))
        take_conversion();
      if (adaptive || !fast_warned)
        speed = model.fastest_bonded_speed();
      if (!adaptive && !fast_warned && speed * dt > max_spacing_fraction * spacing)
        {
          fast_warned = true;
          record.warnings.push_back("step " + std::to_string(step) + " (t = " + sci(time, 6) +
                                    "): a point with intact bonds moves " + sci(speed * dt / spacing, 3) +
                                    " point spacings per step (|v| dt / h; the automatic step keeps this below " +
                                    sci(max_spacing_fraction, 2) +
                                    "): it outruns its neighbours' forces and the run gains energy; lower "
                                    "Solver/Verlet/Fixed dt, or set it to 0 for the automatic step");
        }
      // Asked now: a conversion above makes the contact search anew.
      const Contact *contact = model.contact_forces();
      if (contact && !contact_warned && contact->largest_step_fraction > 0.5)
        {
          contact_warned = true;
          record.warnings.push_back("step " + std::to_string(step) + " (t = " + sci(time, 6) + "): the " +
                                    contact->fastest_description + " moves " +
                                    sci(contact->largest_step_fraction, 3) +
                                    " contact radii per step: contact acts late and bodies interpenetrate (or pass "
                                    "through thin ones); lower the time step (Solver/Verlet/Fixed dt or Safety factor)");
        }
      // The step is complete: what a continued run starts from.
      checkpoint_step(step, time, sums[4] > 0);
      if (sums[4] > 0)
        {
          const double loop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          dt                        = dt_elastic; // for the summary
          access->stop_interrupted(step, time, steps_now, loop_seconds, checkpoint_note);
        }
      report_progress(last);
      return last;
    }

    void
    Verlet::take_conversion()
    {
      RunRecord       &record     = access->record;
      ConditionSet    &conditions = access->conditions;
      MechanicalState &state      = access->state;
      u_previous.resize(state.size());
      v_previous.resize(state.size());
      damage_before = ForceModel::DamageSnapshot(); // of the old bonds: taken again at the next step
      load_previous.clear();
      if (conditions.has_loads())
        for (unsigned int k = 0; k < state.size(); ++k)
          load_previous.push_back(conditions.load(k));
      conditions.take_constraint_state();
      if (fixed_dt == 0)
        dt_elastic = safety_factor * record.dt_stable;
      else if (fixed_dt > record.dt_stable && !unstable_warned)
        {
          unstable_warned = true;
          record.warnings.push_back("step " + std::to_string(step) + ": after cells converted to peridynamics, "
                                    "Fixed dt " + sci(fixed_dt) + " exceeds the stable estimate " +
                                    sci(record.dt_stable) + ": the run may become unstable");
        }
      spacing   = access->discretization.point_spacing();
      base_time = time;
      base_step = step;
    }

    void
    Verlet::check_growth(const double ke, const double new_time)
    {
      const SolverParameters &solver = access->deck.solver;
      RunRecord              &record = access->record;
      const double            reference = std::abs(record.initial_energy) + std::abs(record.external_work);
      const bool              nonfinite = !std::isfinite(ke);
      // With nothing put in yet (a load ramped from zero: its work is
      // counted one drift after the kick it causes) there is no scale;
      // a blow-up from rest still ends non-finite.
      const bool exploding = !nonfinite && ke > 0 && reference > 0 && ke > solver.energy_growth_limit * reference;
      if (!nonfinite && !exploding)
        return;
      const StabilityGuard guard(*access);
      std::string          where = nonfinite ? guard.locate_nonfinite() : "";
      if (exploding)
        {
          const BestPoint fastest = guard.fastest_point();
          where                   = "fastest " + fastest.describe() + ", speed " + sci(fastest.value);
        }
      const double      dt    = record.dt;
      const std::string cause = dt > record.dt_stable ?
                                  "the time step " + sci(dt) + " exceeds the stable estimate " + sci(record.dt_stable) +
                                    ": lower Solver/Verlet/Fixed dt, or set it to 0 for the automatic step" :
                                  "loading or an initial state beyond what the material carries, or a time step too "
                                  "close to the limit (lower Solver/Verlet/Safety factor)";
      // Write the last good state, then stop.
      MechanicalState &state = access->state;
      state.for_each([&](const MechanicalState::DoF &d) {
        d.u = u_previous[d.number];
        d.v = v_previous[d.number];
      });
      state.distribute_displacement();
      access->update_ghosts();
      Postprocess &post = access->post;
      if (post.output.frequency > 0)
        {
          access->model.compute_forces(true);
          post.write_output(step - 1, time);
        }
      AssertThrow(false,
                  ExcMessage(std::string(nonfinite ? "the solution became non-finite" :
                                                     "the kinetic energy grew to " + sci(ke) + ", more than " +
                                                       sci(solver.energy_growth_limit, 3) +
                                                       " times the energy put in (" + sci(reference) + ")") +
                             " at step " + std::to_string(step) + " (t = " + sci(new_time, 6) + "), " + where +
                             ". Likely cause: " + cause +
                             (post.output.frequency > 0 ? ". The last good state is written as step " +
                                                            std::to_string(step - 1) + "." :
                                                          "")));
    }

    void
    Verlet::report_progress(const bool last)
    {
      const SolverParameters &solver  = access->deck.solver;
      const auto              now     = std::chrono::steady_clock::now();
      const double            percent = counted ? 100.0 * step / n_steps :
                                                  100.0 * (time - solver.initial_time) /
                                                    (solver.final_time - solver.initial_time);
      if (percent - last_percent >= 10 || std::chrono::duration<double>(now - last_print).count() > 30 || last)
        {
          const double elapsed = std::chrono::duration<double>(now - start).count();
          access->pcout << "  " << std::setw(5) << std::fixed << std::setprecision(1) << percent << std::defaultfloat
                        << "%  step " << step << (counted ? "/" + std::to_string(n_steps) : "")
                        << "  t = " << sci(time, 6) << "  dt = " << sci(access->record.dt, 4) << "  ETA "
                        << format_seconds(percent > 0 ? elapsed * (100 - percent) / percent : 0) << std::endl;
          last_percent = percent;
          last_print   = now;
        }
    }

    void
    Verlet::finish()
    {
      finished_steps = step;
      finished_time  = time;
      const double loop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      access->record.dt         = dt_elastic; // for the summary
      Postprocess &post         = access->post;
      if (!post.output.is_output_step(step, step))
        {
          // The energy balance needs the final strain energy.
          access->model.compute_forces(true);
          post.global_quantities(step, time);
        }
      post.print_summary(loop_seconds, step);
    }
  } // namespace

  PERIDEAL_REGISTER(TimeIntegrator, Verlet, "Verlet", "explicit velocity-Verlet with lumped mass.")
} // namespace perideal
