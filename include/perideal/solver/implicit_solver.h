#pragma once
// The implicit solve of one step (quasistatic and Newmark): R(u) = V (f(u) +
// b) (- M a(u) for Newmark) = 0 on the free degrees of freedom by Newton's
// method (newton.cc) with a backtracking line search; K du = R by a Krylov
// solver with AMG (the six rigid-body modes as near null space) on the
// assembled tangent, or Jacobian-free (linear_solver.cc). Bonds do not break
// inside Newton; after a converged solve the damage models run, and the step
// is solved again while bonds break.
//
// ImplicitIntegrator is what QuasiStatic and Newmark share: the solver, the
// globals columns (Newton's counts, the reactions) and the reports.

#include <perideal/conditions/condition_set.h>
#include <perideal/model/force_model.h>
#include <perideal/solver/coupled_tangent.h>
#include <perideal/solver/implicit.h>
#include <perideal/solver/tangent.h>
#include <perideal/solver/time_integrator.h>

#include <deal.II/lac/trilinos_precondition.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace perideal
{
  class ContinuumField;
  class ImplicitSolver
  {
  public:
    ImplicitSolver(const SimulatorAccess &access, const ImplicitParameters &parameters);

    /// Tangent sparsity, prescribed DoFs, rigid-body modes (and, if
    /// @p need_supports, the check that conditions remove them). Collective.
    void
    setup(const bool need_supports);
    /// The check alone: an Error if no condition removes some rigid-body
    /// motion (a singular quasistatic problem). Collective.
    void
    check_supports();
    /// Newton, then break bonds and solve again while bonds break; sets
    /// record.last_newton (iterations summed over the solves, the failure)
    /// and record.last_damage_solves. False if a solve failed: the state is
    /// then the failed iterate's (ImplicitIntegrator::advance() returns to
    /// the step's start).
    bool
    solve_step(const unsigned int step);
    /// The tangent's kind and size, for the reports. Collective.
    std::string
    describe_tangent() const;
    /// The Krylov solver of the linear solves (GMRES with force blending).
    const std::string &
    krylov_solver() const
    {
      return linear_solver;
    }

    /// What the external work of an implicit step needs from its start: the
    /// supports' forces, the displacements and the loads.
    struct LoadPathState
    {
      std::vector<double> support, u, load; // per constraint, per DoF, per DoF (empty without loads)
    };
    LoadPathState
    load_path_state() const;
    /// The work of the supports and the loads from @p start to now (trapezoid
    /// rule over the step), summed over ranks.
    double
    load_path_work(const LoadPathState &start) const;

    double              newmark_inertia = 0; // 1/(beta dt^2); 0: quasistatic
    std::vector<double> u_predicted;         // Newmark predictor, per DoF of the mechanical state

  private:
    /// Sets unknown_dofs (pd_free, fe_free); returns their positions and components.
    std::vector<std::pair<dealii::Point<3>, unsigned int>>
    collect_unknowns();
    /// The centroid of @p unknowns and their largest distance from it along an axis. Collective.
    std::pair<std::array<double, 3>, double>
    centre_and_extent(const std::vector<std::pair<dealii::Point<3>, unsigned int>> &unknowns) const;
    void
    check_supports(const std::vector<std::pair<dealii::Point<3>, unsigned int>> &unknowns) const;
    /// Quasistatic: an Error if a point without bonds (pinned) carries a
    /// load at the current time. Collective.
    void
    check_pinned_loads(const unsigned int step) const;
    /// Quasistatic with free rigid-body motions (no condition removes
    /// them): their names, their vectors over the unknowns, an orthonormal
    /// basis of them, and one pinned unknown per motion that makes K
    /// regular (mode_pins). Collective.
    void
    setup_free_modes(const std::vector<std::pair<dealii::Point<3>, unsigned int>> &unknowns);
    /// Motion @p mode (free_rigid_modes()' coefficients) over @p unknowns,
    /// zero at prescribed and pinned entries.
    std::vector<double>
    free_mode_vector(const std::vector<std::pair<dealii::Point<3>, unsigned int>> &unknowns,
                     const std::array<double, 3> &centre, const double extent, const std::array<double, 6> &mode) const;
    /// An Error naming the motions if the current loads push the body along
    /// one of @p named (more than free_mode_tolerance of their norm);
    /// @p when says when. Collective.
    void
    check_free_mode_loads(const std::vector<std::string> &names, const std::vector<std::vector<double>> &named,
                          const std::string &when) const;
    /// The same for the solver's free motions at load step @p step.
    void
    check_free_mode_loads(const unsigned int step) const;
    /// v -= Z Z^T v over the unknowns: no part along the free motions. Collective.
    void
    project_free_modes(double *v) const;
    /// Whether DoF @p k is a free entry of a point without bonds that a
    /// quasistatic solve holds where it is.
    bool
    is_pinned(const unsigned int k) const
    {
      return k < pinned.size() && pinned[k];
    }
    NewtonResult
    solve_newton(const unsigned int step);
    /// R = V (f + b) - M a on the free DoFs of the current displacement;
    /// returns |R| and sets |V (f + b)| over all DoFs (the force scale).
    double
    residual(std::vector<double> &R, double &force_norm);
    /// The unknowns on this rank (unknown_dofs).
    unsigned int
    n_unknowns() const
    {
      return unknown_dofs.size();
    }
    double &
    unknown(const unsigned int j)
    {
      return state.u(unknown_dofs[j]);
    }
    void
    assemble_tangent();
    /// Solves K du = R; returns the Krylov iterations.
    unsigned int
    solve_linear(const std::vector<double> &R, std::vector<double> &du);
    /// residual_products(): K's product from the residual at the unknowns
    /// (saved; restore_unknowns() puts them back), @p R the residual there,
    /// @p first the first unknown of this rank.
    std::function<void(dealii::TrilinosWrappers::MPI::Vector &, const dealii::TrilinosWrappers::MPI::Vector &)>
    residual_operator(const std::vector<double> &R, const dealii::types::global_dof_index first);
    void
    restore_unknowns();
    /// The same without a matrix (Jacobian = Matrix free).
    unsigned int
    solve_matrix_free(const std::vector<double> &R, std::vector<double> &du);

    const SimulatorAccess    &access;
    const ImplicitParameters &implicit;
    MPI_Comm                  comm;
    dealii::ConditionalOStream &pcout;
    dealii::TimerOutput       &timer;
    const PointCloud          &cloud;
    MechanicalState           &state;
    ContinuumField            *continuum; // nullptr without continuum blocks
    bool                       has_continuum;
    bool                       force_blending; // Coupling/Scheme = force blending
    std::string                linear_solver;  // Solver/Implicit/Linear solver; GMRES with force blending

    /// Force blending with a material whose tangent couples over 2 bonds:
    /// the assembled tangent misses terms at the node points
    /// (coupled_tangent.h), so GMRES takes K v from the residual,
    /// -(R(z + e v) - R(z))/e, and the matrix serves its preconditioner.
    bool
    residual_products() const
    {
      return force_blending && tangent && tangent->hops == 2;
    }

    std::unique_ptr<Tangent>        tangent;
    std::unique_ptr<CoupledTangent> coupled_tangent; // with continuum blocks
    bool                            symmetry_reported = false;
    std::vector<std::uint8_t>       constrained_dofs; // per local point entry, ghosts too
    std::vector<std::uint8_t>       pinned;   // quasistatic: per owned point entry, 1 at the free entries of a point without bonds
    unsigned int                    n_pinned = 0; // pinned entries over all ranks
    // Quasistatic free rigid-body motions (empty: none): each named one over
    // the unknowns, an orthonormal basis of them, and per motion the local
    // unknown held at 0 in each linear solve (on the rank that owns it).
    std::vector<std::string>         free_names;
    std::vector<std::vector<double>> free_named, free_basis;
    std::vector<unsigned int>        mode_pins;
    // The unknowns, by DoF number: every point entry (prescribed ones get
    // identity rows), or with continuum blocks the free DoFs of
    // coupled_tangent.h (real points' entries, then FE DoFs).
    std::vector<unsigned int>       unknown_dofs;
    std::vector<unsigned int>       pd_free, fe_free; // with continuum blocks: coupled_tangent.h's
    std::vector<double>             rigid_modes;      // 6 x owned DoFs, column major
    std::vector<double>             block_inverse;    // matrix free: 9 per owned point
    std::unique_ptr<dealii::TrilinosWrappers::PreconditionAMG> amg; // of the current solve
    bool                            rebuild_amg            = true;
    unsigned int                    amg_iterations         = 0; // Krylov iterations with a fresh hierarchy
    bool                            use_finite_differences = false;
    double                          fd_step                = 0;
    std::vector<double>             z_saved, r_plus; // residual_operator(): the unknowns it perturbs, its residual
  };

  /// QuasiStatic and Newmark: an integrator that solves each step with an ImplicitSolver.
  class ImplicitIntegrator : public TimeIntegrator
  {
  public:
    void
    dry_run() override;
    void
    check_stage() override;
    void
    report_summary_speed(const double loop_seconds, const unsigned int steps) const override;
    void
    add_globals(std::vector<std::pair<std::string, double>> &row) const override;

  protected:
    /// Whether the conditions must hold the body (no rigid motion left free).
    virtual bool
    need_supports() const = 0;
    /// The solver, set up.
    ImplicitSolver &
    make_solver();
    /// A scene with continuum blocks needs the assembled Jacobian.
    static void
    check_jacobian(const SolverParameters &solver, const bool has_continuum);
    /// Step @p step, from @p t_start to @p t_end (of length @p dt_step, as
    /// the integrator computes it, passed whole when the step is not cut): @p prepare(t, dt) sets up
    /// the solve of the (sub-)step of length dt that ends at t (prescribed
    /// values, the model's time, Newmark's predictor), @p complete(dt)
    /// follows its converged solve (Newmark's corrector). Each converged
    /// (sub-)step is evaluated (forces, energies), committed, and adds the
    /// loads' work over it. With Adaptive steps a failed solve returns to the
    /// sub-step's start (displacements, velocities, accelerations, bond
    /// damage, released energy; the history is not committed yet) and cuts
    /// it (Solver/Implicit/Adaptive steps); without, or below Minimum step
    /// fraction, it stops the run. Then the step's output is written and
    /// the run stops if a rank has received SIGTERM or SIGINT (one
    /// reduction per step). record.last_newton and last_damage_solves sum
    /// the step's solves, failed ones included.
    void
    advance(const unsigned int step, const double t_start, const double t_end, const double dt_step,
            const unsigned int n_steps,
            const std::function<void(double, double)> &prepare, const std::function<void(double)> &complete);
    /// After cells converted (Adaptivity, checked by advance() after an
    /// accepted step): the solver set up again for the new numbering
    /// (unknowns, sparsity, coupled tangent, rigid modes); Newmark also
    /// takes its accelerations.
    virtual void
    take_conversion();
    /// After a converged (sub-)step of length @p dt: @p complete(dt), the
    /// forces with energy, the commit of the history; returns the loads'
    /// work since @p load_start.
    double
    accept(const double dt, const std::function<void(double)> &complete,
           const ImplicitSolver::LoadPathState &load_start);
    /// Without inertia, after cells converted: step @p step solved again at
    /// its end time @p t_end (the last sub-step's length @p dt) on the new
    /// discretization, bonds breaking as in any solve. The energy the state
    /// gives up beyond the released energy and the loads' work joins the
    /// conversion's jump; a solve that fails stops the run. Collective.
    NewtonResult
    solve_again(const unsigned int step, const double t_end, const double dt,
                const std::function<void(double, double)> &prepare, const std::function<void(double)> &complete);
    /// Seconds since the loop started (start_loop()).
    double
    loop_seconds() const;
    void
    start_loop();

    /// With pd_app --restart: restores the run (restore_checkpoint()) and
    /// sets first_step; stops if nothing is left to run. Collective.
    void
    restore_run(const unsigned int n_steps);
    void
    save_state(CheckpointWriter &out) const override;
    void
    load_state(CheckpointReader &in) override;

    std::unique_ptr<ImplicitSolver> implicit_solver;
    unsigned int                    total_newton = 0, total_linear = 0, total_solves = 0;
    unsigned int                    first_step = 1; // the loop's first step (after a restart, the checkpoint's + 1)

  private:
    /// What a cut returns to; kept, so that a step allocates nothing.
    struct SubStepStart
    {
      std::vector<double>        u, v, a; // per DoF (a: Newmark)
      std::vector<double>        own;     // per constraint: a prescribed velocity's integrated displacement
      ForceModel::DamageState    damage;
      double                     dissipated_energy = 0;
    };
    void
    save(SubStepStart &into) const;
    void
    restore(const SubStepStart &from) const;

    std::chrono::steady_clock::time_point start;
    unsigned int completed_step = 0; // the last step advance() completed, and its time
    double       completed_time = 0;
    double       step_fraction = 1; // of a step, the sub-steps' length (Adaptive steps)
    SubStepStart sub_step_start;
  };
} // namespace perideal
