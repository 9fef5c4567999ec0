// Implicit dynamics by Newmark-beta (Solver/Type = Newmark): step k solves
//   R(u) = V (f(u) + b) - M a(u) = 0,  a(u) = (u - u_pred) / (beta dt^2),
//   u_pred = u + dt v + dt^2/2 (1 - 2 beta) a,  v = v_pred + gamma dt a(u),
// with M = rho V (a PD point's consistent mass is its own) and the lumped FE
// mass, by Newton's method (implicit_solver.h; the tangent gains M / (beta
// dt^2)). Beta and gamma are Solver/Implicit/Newmark beta and gamma.

#include <perideal/adaptivity/adaptivity.h>
#include <perideal/base/format.h>
#include <perideal/model/force_model.h>
#include <perideal/output/postprocess.h>
#include <perideal/simulation/deck.h>
#include <perideal/solver/implicit_solver.h>


namespace perideal
{
  using namespace dealii;

  namespace
  {
    class Newmark : public ImplicitIntegrator
    {
    public:
      // Solver/Implicit/Newmark beta and gamma, next to the Newton keys they
      // go with.
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Implicit");
        prm.declare_entry("Newmark beta", "0.25", Patterns::Double(0, 0.5),
                          "Newmark's beta; 1/4 with gamma 1/2 is the trapezoidal rule: unconditionally "
                          "stable, second order, no numerical damping.");
        prm.declare_entry("Newmark gamma", "0.5", Patterns::Double(0, 1),
                          "Newmark's gamma; above 1/2 damps high frequencies (unconditionally stable for "
                          "gamma >= 1/2 and beta >= (gamma + 1/2)^2 / 4).");
        prm.leave_subsection();
      }

      void
      parse_parameters(ParameterHandler &prm) override
      {
        prm.enter_subsection("Implicit");
        beta  = prm.get_double("Newmark beta");
        gamma = prm.get_double("Newmark gamma");
        prm.leave_subsection();
        // Below 1/2 Newmark's numerical damping is negative: the energy grows
        // every step, whatever the step (a run of box.prm with gamma = 0: 18%
        // energy error in two steps, exit 0).
        AssertThrow(gamma >= 0.5,
                    ExcMessage("Solver/Implicit/Newmark gamma must be at least 0.5, got " +
                               Utilities::to_string(gamma) +
                               ": below it the scheme adds energy every step (unstable for any time step); "
                               "0.5 conserves energy, more damps it"));
        AssertThrow(beta > 0, ExcMessage("Solver/Implicit/Newmark beta must be positive (beta = 0 is the explicit "
                                         "central difference: use Solver/Type = Verlet)"));
      }

      void
      check_parameters(const SolverParameters &solver, const bool has_continuum) const override
      {
        AssertThrow(solver.requested_steps > 0 && solver.final_time > solver.initial_time,
                    ExcMessage("Solver/Number of steps and Final time: the Newmark solver takes Number of steps "
                               "equal steps from Initial time to Final time; set both"));
        check_jacobian(solver, has_continuum);
      }

      void
      run() override
      {
        do_initial_timestep();
        for (step = first_step; step <= n_steps; ++step)
          do_timestep();
        finish();
      }

      void
      report_summary_step() const override
      {
        const RunRecord &record = access->record;
        access->pcout << "  time step:              " << sci(record.dt, 6) << " ("
                      << sci(record.dt / record.dt_stable, 3) << " x the explicit stable estimate "
                      << sci(record.dt_stable, 6) << ")\n";
      }

    protected:
      bool
      need_supports() const override
      {
        return false;
      }
      /// After cells converted: the solver for the new numbering, and the
      /// accelerations from the equation of motion, as at the start.
      void
      take_conversion() override
      {
        ImplicitIntegrator::take_conversion();
        accelerations_from_forces();
        v_predicted.assign(access->state.size(), 0.0);
        implicit_solver->u_predicted.assign(access->state.size(), 0.0);
      }

    private:
      /// a = f / rho at every DoF (virtual points have no mass: they follow
      /// the FE field), from the forces evaluated last.
      void
      accelerations_from_forces()
      {
        MechanicalState &state = access->state;
        state.acceleration.assign(state.size(), 0.0);
        state.for_each([&](const MechanicalState::DoF &d) {
          state.acceleration[d.number] = d.density > 0 ? d.f / d.density : 0.0;
        });
      }
      void
      do_initial_timestep();
      void
      do_timestep();
      void
      finish();

      unsigned int n_steps = 0, step = 0;
      double       t0 = 0, beta = 0.25, gamma = 0.5;
      std::vector<double>              v_predicted; // per DoF
    };

    void
    Newmark::do_initial_timestep()
    {
      const SolverParameters &solver = access->deck.solver;
      MechanicalState        &state  = access->state;
      n_steps                        = solver.requested_steps;
      t0                             = solver.initial_time;
      AssertThrow(solver.final_time > solver.initial_time,
                  ExcMessage("Newmark: Final time (" + sci(solver.final_time, 6) + ") must be after the start (t = " +
                             sci(solver.initial_time, 6) + ", where the solver before ended)"));
      access->record.dt              = (solver.final_time - solver.initial_time) / n_steps;
      const bool restart = !access->restart.empty(), continues = access->continues;
      if (restart || !continues)
        access->post.output.initialize(access->comm);
      if (!continues)
        access->conditions.apply_initial_conditions(solver.initial_time);
      access->model.breaking_allowed = false;
      if (access->adaptivity)
        access->adaptivity->use_integrator(false, true);
      make_solver();
      access->stop_if_interrupted_in_setup();

      // The initial acceleration from the equation of motion.
      state.acceleration.assign(state.size(), 0.0);
      if (restart)
        restore_run(n_steps);
      else
        {
          // A stage that continues starts from the forces the one before left.
          if (!continues)
            access->evaluate_initial_state();
          accelerations_from_forces();
          if (!continues)
            access->record_initial_state(n_steps, t0);
        }
      // (A restart after a conversion has set the solver up again.)
      access->pcout << "Newmark (beta " << beta << ", gamma " << gamma << "): " << n_steps << " steps of "
                    << sci(access->record.dt, 6) << " from t = " << t0 << "; tangent "
                    << implicit_solver->describe_tangent() << std::endl;

      v_predicted.assign(state.size(), 0.0);
      implicit_solver->u_predicted.assign(state.size(), 0.0);
      start_loop();
    }

    void
    Newmark::do_timestep()
    {
      MechanicalState    &state      = access->state;
      RunRecord          &record     = access->record;
      ConditionSet       &conditions = access->conditions;
      const double        dt         = record.dt;
      const double        time       = t0 + step * dt;
      std::vector<double> &a         = state.acceleration;

      access->pcout << "Step " << step << "/" << n_steps << ", t = " << sci(time, 6) << std::endl;
      advance(
        step, t0 + (step - 1) * dt, time, dt, n_steps,
        [&](const double t, const double h) {
          // The solver of this (sub-)step: a conversion sets up a new one.
          ImplicitSolver &newton = *implicit_solver;
          state.for_each([&](const MechanicalState::DoF &d) {
            const unsigned int k  = d.number;
            newton.u_predicted[k] = d.u + h * d.v + 0.5 * h * h * (1 - 2 * beta) * a[k];
            v_predicted[k]        = d.v + h * (1 - gamma) * a[k];
            d.u                   = newton.u_predicted[k];
          });
          conditions.apply_prescribed(t, h);
          access->model.set_time(t, h);
          if (conditions.loads_depend_on_time)
            conditions.evaluate_loads(t);
          conditions.check_condition_values(conditions.first_nonfinite_condition(t), t);
          newton.newmark_inertia = 1 / (beta * h * h);
        },
        [&](const double h) {
          const ImplicitSolver &newton = *implicit_solver;
          state.for_each([&](const MechanicalState::DoF &d) {
            const unsigned int k = d.number;
            a[k]                 = (d.u - newton.u_predicted[k]) * newton.newmark_inertia;
            d.v                  = v_predicted[k] + gamma * h * a[k];
          });
          state.distribute_velocity();
        });
    }

    void
    Newmark::finish()
    {
      finished_steps = n_steps;
      finished_time  = t0 + n_steps * access->record.dt;
      const double seconds = loop_seconds();
      access->pcout << "\nNewmark: " << n_steps << " steps, " << total_newton << " Newton iterations, " << total_linear
                    << " " << (implicit_solver ? implicit_solver->krylov_solver() : access->deck.solver.implicit.linear_solver) << " iterations in " << sci(seconds, 4) << " s"
                    << std::endl;
      access->post.global_quantities(n_steps, t0 + n_steps * access->record.dt);
      access->post.print_summary(seconds, n_steps);
    }
  } // namespace

  PERIDEAL_REGISTER(TimeIntegrator, Newmark, "Newmark",
                    "implicit dynamics, Number of steps equal steps from Initial time to Final time, each solved "
                    "by Newton's method (subsection Implicit).")
} // namespace perideal
