#pragma once
// Parameters of the implicit solvers (Solver/Implicit), quasistatic and
// Newmark-beta: Newton with a backtracking line search, a Krylov solver (CG,
// or GMRES) preconditioned by Trilinos ML AMG with the six rigid-body modes as
// near null space, the re-solve of a step while bonds break, and Newmark's
// beta and gamma, and the cuts of a step whose solve fails. The solver is ImplicitSolver (implicit_solver.h), the
// integrators QuasiStatic and Newmark.

#include <perideal/base/input.h>

#include <string>

namespace perideal
{
  struct ImplicitParameters
  {
    double       tolerance          = 1e-8;
    double       absolute_tolerance = 0;
    unsigned int max_newton         = 25;
    bool         line_search        = true;
    std::string  linear_solver      = "CG";
    std::string  preconditioner     = "AMG";
    double       aggregation_threshold = 0; // 0: by the tangent's coupling
    double       linear_tolerance   = 1e-10;
    unsigned int max_linear         = 1000;
    std::string  tangent            = "Analytic";
    std::string  jacobian           = "Assembled";
    double       keep_tangent_contraction = 0; // an iteration that reduced |R| this much keeps its tangent; 0: never
    unsigned int max_damage_solves  = 20;
    bool         adaptive_steps     = true;  // cut a step whose solve fails
    double       min_step_fraction  = 1e-3; // the smallest sub-step, per step

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);
  };
} // namespace perideal
