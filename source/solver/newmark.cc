// Implicit dynamics by Newmark-beta (Solver/Type = Newmark): step k solves
//   R(u) = V (f(u) + b) - M a(u) = 0,  a(u) = (u - u_pred) / (beta dt^2),
//   u_pred = u + dt v + dt^2/2 (1 - 2 beta) a,  v = v_pred + gamma dt a(u),
// with M = rho V (a PD point's consistent mass is its own) and the lumped FE
// mass, by Newton's method (implicit_solver.h; the tangent gains M / (beta
// dt^2)). Beta and gamma are Solver/Implicit/Newmark beta and gamma.

#include <perideal/base/format.h>
#include <perideal/continuum/coupling.h>
#include <perideal/model/force_model.h>
#include <perideal/output/postprocess.h>
#include <perideal/simulation/deck.h>
#include <perideal/solver/implicit_solver.h>


namespace perideal
{
  using namespace dealii;

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
      for (step = 1; step <= n_steps; ++step)
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

  private:
    void
    do_initial_timestep();
    void
    do_timestep();
    void
    finish();

    unsigned int n_steps = 0, step = 0;
    double       t0 = 0, beta = 0.25, gamma = 0.5;
    const std::vector<unsigned int> *fe_dofs = nullptr; // the FE DoFs that carry equations
    std::vector<double>              v_predicted, fe_v_predicted;
  };

  void
  Newmark::do_initial_timestep()
  {
    const SolverParameters &solver    = access->deck.solver;
    MechanicalState        &state     = access->state;
    ContinuumField         *continuum = access->coupling ? &access->coupling->continuum : nullptr;
    n_steps                           = solver.requested_steps;
    t0                                = solver.initial_time;
    access->record.dt                 = (solver.final_time - solver.initial_time) / n_steps;
    access->post.output.initialize(access->comm);
    access->conditions.apply_initial_conditions(solver.initial_time);
    access->model.breaking_allowed = false;
    ImplicitSolver &newton         = make_solver();
    access->stop_if_interrupted_in_setup();
    const unsigned int n = dim * access->discretization.cloud.n_owned();

    // The FE nodes of continuum blocks: the same steps over the owned DoFs
    // that carry equations (hanging ones follow their masters).
    static const std::vector<unsigned int> no_dofs;
    fe_dofs = continuum ? &continuum->free : &no_dofs;
    fe_v_predicted.resize(fe_dofs->size());
    if (continuum)
      {
        newton.fe_u_predicted.assign(continuum->U.locally_owned_size(), 0.0);
        state.fe_acceleration.assign(continuum->U.locally_owned_size(), 0.0);
      }

    // The initial acceleration from the equation of motion (virtual points
    // have no mass: they follow the FE field).
    access->evaluate_initial_state();
    state.acceleration.resize(n);
    for (unsigned int k = 0; k < n; ++k)
      state.acceleration[k] =
        state.mass_density[k / dim] > 0 ? state.force.local_element(k) / state.mass_density[k / dim] : 0.0;
    for (const unsigned int l : *fe_dofs)
      state.fe_acceleration[l] = continuum->F.local_element(l) / continuum->mass.local_element(l);
    access->record_initial_state(n_steps, t0);
    access->pcout << "Newmark (beta " << beta << ", gamma " << gamma << "): " << n_steps << " steps of "
                  << sci(access->record.dt, 6) << " from t = " << t0 << "; tangent " << newton.describe_tangent()
                  << std::endl;

    v_predicted.resize(n);
    newton.u_predicted.resize(n);
    start_loop();
  }

  void
  Newmark::do_timestep()
  {
    MechanicalState &state      = access->state;
    RunRecord       &record     = access->record;
    ConditionSet    &conditions = access->conditions;
    ImplicitSolver  &newton     = *implicit_solver;
    ContinuumField  *continuum  = access->coupling ? &access->coupling->continuum : nullptr;
    const double     dt         = record.dt;
    const double     time       = t0 + step * dt;
    const unsigned int n        = newton.u_predicted.size();
    double *const      u        = state.displacement.begin();
    double *const      v        = state.velocity.begin();
    double *const      U        = continuum ? continuum->U.begin() : nullptr;
    double *const      V        = continuum ? continuum->V.begin() : nullptr;
    std::vector<double> &a = state.acceleration, &fe_a = state.fe_acceleration;

    access->pcout << "Step " << step << "/" << n_steps << ", t = " << sci(time, 6) << std::endl;
    const ImplicitSolver::LoadPathState step_start = newton.load_path_state();
    for (unsigned int k = 0; k < n; ++k)
      {
        newton.u_predicted[k] = u[k] + dt * v[k] + 0.5 * dt * dt * (1 - 2 * beta) * a[k];
        v_predicted[k]        = v[k] + dt * (1 - gamma) * a[k];
        u[k]                  = newton.u_predicted[k];
      }
    for (unsigned int j = 0; j < fe_dofs->size(); ++j)
      {
        const unsigned int l     = (*fe_dofs)[j];
        newton.fe_u_predicted[l] = U[l] + dt * V[l] + 0.5 * dt * dt * (1 - 2 * beta) * fe_a[l];
        fe_v_predicted[j]        = V[l] + dt * (1 - gamma) * fe_a[l];
        U[l]                     = newton.fe_u_predicted[l];
      }
    conditions.apply_prescribed(time, dt);
    if (conditions.loads_depend_on_time)
      conditions.evaluate_loads(time);
    conditions.check_condition_values(conditions.first_nonfinite_condition(time), time);
    newton.newmark_inertia = 1 / (beta * dt * dt);
    newton.solve_step(step);
    for (unsigned int k = 0; k < n; ++k)
      {
        a[k] = (u[k] - newton.u_predicted[k]) * newton.newmark_inertia;
        v[k] = v_predicted[k] + gamma * dt * a[k];
      }
    for (unsigned int j = 0; j < fe_dofs->size(); ++j)
      {
        const unsigned int l = (*fe_dofs)[j];
        fe_a[l]              = (U[l] - newton.fe_u_predicted[l]) * newton.newmark_inertia;
        V[l]                 = fe_v_predicted[j] + gamma * dt * fe_a[l];
      }
    if (continuum && continuum->hanging.n_constraints() > 0)
      continuum->hanging.distribute(continuum->V);
    finish_step(step_start, step, time, n_steps);
  }

  void
  Newmark::finish()
  {
    const double seconds = loop_seconds();
    access->pcout << "\nNewmark: " << n_steps << " steps, " << total_newton << " Newton iterations, " << total_linear
                  << " " << access->deck.solver.implicit.linear_solver << " iterations in " << sci(seconds, 4) << " s"
                  << std::endl;
    access->post.global_quantities(n_steps, t0 + n_steps * access->record.dt);
    access->post.print_summary(seconds, n_steps);
  }

  PERIDEAL_REGISTER(TimeIntegrator, Newmark, "Newmark",
                    "implicit dynamics, Number of steps equal steps from Initial time to Final time, each solved "
                    "by Newton's method (subsection Implicit).")
} // namespace perideal
