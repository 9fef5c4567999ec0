// Quasistatic load stepping (Solver/Type = QuasiStatic), Peridigm's
// QuasiStatic: load step k sets the prescribed displacements and body forces
// at pseudo-time t_k and solves R(u) = V (f(u) + b) = 0 on the free degrees of
// freedom by Newton's method (implicit_solver.h); bonds break between solves,
// and the step is solved again while they do. No motion between load steps,
// so no kinetic energy; the work of supports and loads is the trapezoid rule
// over each step.
//
// The points are at rest between load steps (Solver/QuasiStatic/Velocity =
// rest), or (= load step, as Peridigm's QuasiStatic stores and writes it)
// each free point at the velocity of its load step, (u_n - u_(n-1)) / dt;
// the summary's energy balance counts no kinetic energy either way. A Solver
// stage after it starts with the free points at rest, or (Solver
// stages/NAME/Velocity after quasistatic = load step) with every point at
// the velocity of the last load step, Peridigm's hand-off: finish() sets it.
// The displacement at the start of the load step is kept for both, and a
// checkpoint carries it.

#include <perideal/adaptivity/adaptivity.h>
#include <perideal/base/format.h>
#include <perideal/model/force_model.h>
#include <perideal/output/checkpoint.h>
#include <perideal/output/postprocess.h>
#include <perideal/simulation/deck.h>
#include <perideal/solver/implicit_solver.h>

#include <deal.II/base/mpi.h>


namespace perideal
{
  using namespace dealii;

  namespace
  {
    class QuasiStatic : public ImplicitIntegrator
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("QuasiStatic");
        prm.declare_entry("Velocity", "rest", Patterns::Selection("rest|load step"),
                          "The points' velocity in the load steps. rest: none (the load steps are a "
                          "pseudo-time without motion). load step: after each load step every free point "
                          "at (u_n - u_(n-1)) / dt, dt the load step's length, as Peridigm's QuasiStatic "
                          "stores and writes it: in the field files (Velocity) and the globals' "
                          "kinetic_energy. The summary's energy balance counts no kinetic energy either way; "
                          "the converter writes load step.");
        prm.leave_subsection();
      }

      void
      parse_parameters(ParameterHandler &prm) override
      {
        prm.enter_subsection("QuasiStatic");
        velocity_of_load_steps = prm.get("Velocity") == "load step";
        prm.leave_subsection();
      }

      void
      check_parameters(const SolverParameters &solver, const bool has_continuum) const override
      {
        AssertThrow(solver.requested_steps > 0,
                    ExcMessage("Solver/Number of steps: the quasistatic solver needs the number of load steps (> 0)"));
        check_jacobian(solver, has_continuum);
      }

      std::string
      loop_name() const override
      {
        return "load steps";
      }

      void
      run() override
      {
        do_initial_step();
        for (step = first_step; step <= n_steps; ++step)
          do_load_step();
        finish();
      }

    protected:
      bool
      need_supports() const override
      {
        return true;
      }
      /// After cells converted: the solver of the new numbering, and the
      /// load step's start in it, u - v dt (v carried over: the load step's
      /// with Velocity = load step, 0 at rest), for the velocity of the
      /// step's solve on the new discretization.
      void
      take_conversion() override
      {
        ImplicitIntegrator::take_conversion();
        MechanicalState &state = access->state;
        u_step_start.resize(state.size());
        for (unsigned int k = 0; k < state.size(); ++k)
          u_step_start[k] = state.u(k) - (velocity_of_load_steps ? state.v(k) * dt_load : 0.0);
      }
      void
      save_state(CheckpointWriter &out) const override;
      void
      load_state(CheckpointReader &in) override;

    private:
      void
      do_initial_step();
      void
      do_load_step();
      void
      finish();
      /// Before the next Solver stage: its starting velocity.
      void
      hand_off();
      /// Every free entry (and the prescribed ones too if @p held_too) at
      /// (u - u_step_start) / dt_load; returns the kinetic energy that
      /// gives (all ranks).
      double
      set_load_step_velocity(const bool held_too);

      unsigned int n_steps = 0, step = 0;
      double       t0 = 0, t1 = 0, dt_load = 0;
      std::vector<double> u_step_start; // per DoF: u at the start of the load step
      bool                velocity_of_load_steps = false; // Velocity = load step
    };

    void
    QuasiStatic::do_initial_step()
    {
      const SolverParameters &solver = access->deck.solver;
      n_steps                        = solver.requested_steps;
      t0                             = solver.initial_time;
      t1      = solver.final_time > solver.initial_time ? solver.final_time : solver.initial_time + 1;
      dt_load = (t1 - t0) / n_steps;
      access->record.dt = dt_load;
      const bool restart = !access->restart.empty(), continues = access->continues;
      if (restart || !continues)
        access->post.output.initialize(access->comm);
      if (!continues)
        access->conditions.apply_initial_conditions(solver.initial_time);
      access->model.breaking_allowed = false;
      if (access->adaptivity)
        access->adaptivity->use_integrator(false, false);
      make_solver();
      access->stop_if_interrupted_in_setup();
      access->pcout << "Quasistatic: " << n_steps << " load steps from t = " << t0 << " to " << t1 << "; tangent "
                    << implicit_solver->describe_tangent() << std::endl;

      if (restart)
        restore_run(n_steps);
      else if (!continues)
        {
          access->evaluate_initial_state();
          access->record_initial_state(n_steps, t0);
        }
      start_loop();
    }

    void
    QuasiStatic::do_load_step()
    {
      ConditionSet    &conditions = access->conditions;
      const double     time       = t0 + step * dt_load;
      access->pcout << "Load step " << step << "/" << n_steps << ", t = " << sci(time, 6) << std::endl;
      MechanicalState &state = access->state;
      u_step_start.resize(state.size());
      for (unsigned int k = 0; k < state.size(); ++k)
        u_step_start[k] = state.u(k);
      advance(
        step, t0 + (step - 1) * dt_load, time, dt_load, n_steps,
        [&](const double t, const double dt) {
          conditions.apply_prescribed(t, dt);
          access->model.set_time(t, dt);
          // No motion between load steps (apply_prescribed sets the
          // supports' rate), so no kinetic energy.
          access->state.set_velocity_zero();
          if (conditions.loads_depend_on_time)
            conditions.evaluate_loads(t);
          conditions.check_condition_values(conditions.first_nonfinite_condition(t), t);
        },
        [&](double) {
          // After each sub-step: the last one's is the load step's.
          // Peridigm's QuasiStatic gives every point, prescribed or not, its
          // load step's difference quotient.
          if (velocity_of_load_steps)
            set_load_step_velocity(true);
        });
    }

    void
    QuasiStatic::save_state(CheckpointWriter &out) const
    {
      ImplicitIntegrator::save_state(out);
      out.section("quasistatic");
      out.put(u_step_start);
    }

    void
    QuasiStatic::load_state(CheckpointReader &in)
    {
      ImplicitIntegrator::load_state(in);
      in.section("quasistatic");
      in.get(u_step_start);
      in.expect(u_step_start.size() == access->state.size(),
                "the displacement at the start of the load step has " + std::to_string(u_step_start.size()) +
                  " entries on this rank, the state " + std::to_string(access->state.size()));
    }

    void
    QuasiStatic::hand_off()
    {
      // The stage after this solver, if any, and what it starts with: the
      // free entries are at rest now (set_velocity_zero() each step), the
      // prescribed ones at their condition's rate.
      if (access->last_stage || u_step_start.size() != access->state.size())
        return;
      const SolverStage &next = access->deck.stages[access->stage];
      if (!next.velocity_of_load_step)
        return;
      const double kinetic = set_load_step_velocity(false);
      // Energy put in by the hand-off: the next solver's balance counts it.
      access->record.initial_energy += kinetic;
      access->pcout << "\nSolver stages/" << next.name << " starts at the velocity of the last load step, (u_n - "
                    << "u_(n-1)) / dt (Velocity after quasistatic = load step): kinetic energy " << sci(kinetic, 6)
                    << std::endl;
    }

    double
    QuasiStatic::set_load_step_velocity(const bool held_too)
    {
      MechanicalState                 &state   = access->state;
      const std::vector<std::uint8_t> &held    = access->conditions.prescribed;
      double                           kinetic = 0;
      for (unsigned int k = 0; k < state.size(); ++k)
        if (held_too || !held[k])
          {
            state.v(k) = (state.u(k) - u_step_start[k]) / dt_load;
            kinetic += 0.5 * state.mass(k) * state.v(k) * state.v(k);
          }
      state.distribute_velocity();
      state.velocity.update_ghost_values();
      return Utilities::MPI::sum(kinetic, access->comm);
    }

    void
    QuasiStatic::finish()
    {
      finished_steps = n_steps;
      finished_time  = t1;
      const double seconds = loop_seconds();
      Postprocess &post    = access->post;
      // The energy balance needs the final strain energy.
      if (!post.output.is_output_step(n_steps, n_steps))
        post.global_quantities(n_steps, t1);
      // A load step's velocity (Velocity = load step) is no motion: no
      // kinetic energy in the balance.
      if (velocity_of_load_steps)
        access->record.last_kinetic_energy = 0;
      access->pcout << "\nQuasistatic: " << n_steps << " load steps, " << total_solves << " solves, " << total_newton
                    << " Newton iterations, " << total_linear << " " << (implicit_solver ? implicit_solver->krylov_solver() : access->deck.solver.implicit.linear_solver)
                    << " iterations in " << sci(seconds, 4) << " s" << std::endl;
      post.print_summary(seconds, n_steps);
      hand_off();
    }
  } // namespace

  PERIDEAL_REGISTER(TimeIntegrator, QuasiStatic, "QuasiStatic",
                    "Number of steps load steps from Initial time to Final time (a pseudo-time; 0 to 1 if Final "
                    "time is not after Initial time), each solved by Newton's method (subsection Implicit).")
} // namespace perideal
