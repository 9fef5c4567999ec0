// Implicit dynamics by Newmark-beta (Solver/Type = Newmark): step k solves
//   R(u) = V (f(u) + b) - M a(u) = 0,  a(u) = (u - u_pred) / (beta dt^2),
//   u_pred = u + dt v + dt^2/2 (1 - 2 beta) a,  v = v_pred + gamma dt a(u),
// with M = rho V (a PD point's consistent mass is its own) and the lumped FE
// mass, by Newton's method (implicit_solver.h; the tangent gains M / (beta
// dt^2)). Beta and gamma are Solver/Implicit/Newmark beta and gamma.

#include <perideal/base/format.h>
#include <perideal/base/interrupt.h>
#include <perideal/continuum/coupling.h>
#include <perideal/model/force_model.h>
#include <perideal/output/postprocess.h>
#include <perideal/simulation/deck.h>
#include <perideal/solver/implicit_solver.h>

#include <chrono>

namespace perideal
{
  using namespace dealii;

  class Newmark : public ImplicitIntegrator
  {
  public:
    static void
    declare_parameters(ParameterHandler &)
    {}

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
    unsigned int total_newton = 0, total_linear = 0;
    const std::vector<unsigned int> *fe_dofs = nullptr; // the FE DoFs that carry equations
    std::vector<double>              v_predicted, fe_v_predicted;
    std::chrono::steady_clock::time_point start;
  };

  void
  Newmark::do_initial_timestep()
  {
    const SolverParameters &solver    = access->deck.solver;
    MechanicalState        &state     = access->state;
    ContinuumField         *continuum = access->coupling ? &access->coupling->continuum : nullptr;
    n_steps                           = solver.requested_steps;
    t0                                = solver.initial_time;
    beta                              = solver.implicit.beta;
    gamma                             = solver.implicit.gamma;
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
    start = std::chrono::steady_clock::now();
  }

  void
  Newmark::do_timestep()
  {
    MechanicalState &state      = access->state;
    RunRecord       &record     = access->record;
    ConditionSet    &conditions = access->conditions;
    Postprocess     &post       = access->post;
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
    total_newton += record.last_newton.newton_iterations;
    total_linear += record.last_newton.linear_iterations;
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
    state.displacement.update_ghost_values();
    access->model.compute_forces(true);
    record.external_work += newton.load_path_work(step_start);
    if (post.output.is_output_step(step, n_steps))
      post.write_output(step, time, post.output.is_globals_step(step, n_steps),
                        post.output.is_field_step(step, n_steps));
    // SIGTERM, SIGINT: stop after the step (one reduction per step).
    if (interrupt_signal(access->comm) != 0)
      access->stop_interrupted(step, time, n_steps,
                               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }

  void
  Newmark::finish()
  {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
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
