#pragma once
// Parameters of the quasistatic solver (Solver/QuasiStatic): load steps over
// a pseudo-time, Newton with a backtracking line search, a Krylov solver
// (CG, or GMRES) preconditioned by Trilinos ML AMG with the six rigid-body
// modes as near null space, and the re-solve of a step while bonds break.
// The solver itself is Simulation::run_quasistatic() (quasistatic.cc).

#include <perideal/base/input.h>

#include <string>

namespace perideal
{
  struct QuasiStaticParameters
  {
    double       tolerance          = 1e-8;
    double       absolute_tolerance = 0;
    unsigned int max_newton         = 25;
    bool         line_search        = true;
    std::string  linear_solver      = "CG";
    std::string  preconditioner     = "AMG";
    double       linear_tolerance   = 1e-10;
    unsigned int max_linear         = 1000;
    std::string  tangent            = "Analytic";
    unsigned int max_damage_solves  = 20;

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);
  };
} // namespace perideal
