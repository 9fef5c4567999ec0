// The parameters of the implicit solvers (Solver/Implicit): Newton, the
// linear solver and its preconditioner, the re-solves while bonds break
// and the cuts of a step whose solve fails (implicit_solver.h, quasistatic.cc, newmark.cc; Newmark's own beta and gamma
// are in newmark.cc).

#include <perideal/solver/implicit.h>

#include <deal.II/base/utilities.h>

namespace perideal
{
  using namespace dealii;

  void
  ImplicitParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Tolerance", "1e-8", Patterns::Double(0),
                      "Newton stops when |R| <= Tolerance x max(|R| at the start of the solve, |F|): R "
                      "the residual on the free degrees of freedom (V(f + b), minus M a for Newmark), F "
                      "= V(f + b) on all of them (the forces in the body, reactions included).");
    prm.declare_entry("Absolute tolerance", "0", Patterns::Double(0),
                      "Newton also stops when |R| <= this (force units); 0: off.");
    prm.declare_entry("Maximum Newton iterations", "25", Patterns::Integer(1),
                      "A solve that has not converged after this many iterations has failed: its step is cut "
                      "(Adaptive steps), or the run stops with an error.");
    prm.declare_entry("Line search", "true", Patterns::Bool(),
                      "Backtracking line search on |R|: halve the Newton step (at most 10 times) "
                      "until |R| decreases.");
    prm.declare_entry("Linear solver", "CG", Patterns::Selection("CG|GMRES"),
                      "Krylov solver for K du = R. K is symmetric for PMB and LPS: CG. GMRES for "
                      "models whose tangent is not symmetric. With Coupling/Scheme = force blending "
                      "the coupled tangent is not symmetric and GMRES is used whatever this says.");
    prm.declare_entry("Preconditioner", "AMG", Patterns::Selection("AMG|Jacobi"),
                      "AMG: Trilinos ML smoothed aggregation with the six rigid-body modes as near "
                      "null space; Jacobi: the diagonal (for comparison).");
    prm.declare_entry("AMG aggregation threshold", "0", Patterns::Double(0, 1),
                      "ML drops the couplings weaker than this (relative to the diagonal) before it "
                      "aggregates. 0: automatic, 1e-4 (deal.II's default) for a tangent that couples "
                      "a point to its family only (PMB), 0.005 for one that couples it to its "
                      "neighbors' families (LPS): with hundreds of couplings per row, LPS needs the "
                      "weak ones dropped (12^3 cube: 27 CG iterations with 1e-4, 13 with 0.005), "
                      "but not too many (dog-bone of doc/examples/dogbone_tensile: 29 with 0.005, "
                      "77 with 0.02, 200 with 0.1), while PMB's counts grow with the mesh at 0.1 "
                      "(10^3 to 30^3 points: 8 to 34) and stay nearly constant at 1e-4 (13 to 18).");
    prm.declare_entry("Linear tolerance", "1e-10", Patterns::Double(0),
                      "The Krylov solver stops at |K du - R| <= this x |R|. Newton converges "
                      "quadratically only while this is far below the Newton tolerance.");
    prm.declare_entry("Maximum linear iterations", "1000", Patterns::Integer(1),
                      "More stops the run with an error.");
    prm.declare_entry("Tangent", "Analytic", Patterns::Selection("Analytic|Finite differences"),
                      "Analytic: each material's own tangent (PMB, LPS, Elastic plastic, Viscoelastic); "
                      "with a material that has none (the correspondence models) every solve uses finite "
                      "differences, as the set-up line says. Finite differences: central differences "
                      "of the force for every material (6 force evaluations per colour; see the "
                      "set-up report for the number of colours).");
    prm.declare_entry("Jacobian", "Assembled", Patterns::Selection("Assembled|Matrix free"),
                      "Assembled: the tangent in a Trilinos sparse matrix, Krylov solver and "
                      "preconditioner as chosen above. Matrix free: Jacobian-free Newton-Krylov for "
                      "scenes whose matrix does not fit: the Linear solver (CG, or GMRES(50)) on finite "
                      "differences of the residual (K v ~ -(R(u + e v) - R(u))/e, one force evaluation "
                      "per iteration), "
                      "preconditioned by the inverse 3x3 diagonal blocks of the analytic tangent (9 "
                      "numbers per point instead of the matrix). Needs materials with an analytic tangent.");
    prm.declare_entry("Keep tangent below contraction", "0", Patterns::Double(0, 1),
                      "0: a new tangent every iteration (full Newton, quadratic convergence). Above 0 (e.g. "
                      "1e-3): a Newton iteration that reduced |R| by this factor or more (|R_new| <= this x "
                      "|R|, with a full step) leaves its tangent and preconditioner to the next iteration: the "
                      "problem is nearly linear there, and the kept tangent converges about as fast as a new "
                      "one (a linear problem's second iteration costs one linear solve, no assembly; the last "
                      "iteration converges linearly instead of quadratically). An iteration on a kept tangent "
                      "that does not reduce |R| is done again with a new tangent.");
    prm.declare_entry("Maximum damage solves", "20", Patterns::Integer(1),
                      "After a converged solve the damage models break bonds; the step is solved "
                      "again while bonds break, at most this many times (then a warning).");
    prm.declare_entry("Adaptive steps", "true", Patterns::Bool(),
                      "A step whose Newton solve fails (Maximum Newton iterations reached, a residual that is "
                      "not finite, no descent) is cut: the state returns to the step's start (displacements, "
                      "velocities, bond damage, history) and the step is done as sub-steps of half its length, "
                      "halved again while a solve fails; after a sub-step whose solves took at most half of "
                      "Maximum Newton iterations the sub-steps double again, up to the whole step (the size "
                      "carries over to the next steps). Output and the globals stay at the steps' ends; each "
                      "cut is reported, and the summary counts them. false: a failed solve stops the run.");
    prm.declare_entry("Minimum step fraction", "0.001", Patterns::Double(0, 1),
                      "Adaptive steps: a solve that fails at a sub-step that cannot be halved without going "
                      "below this fraction of a step stops the run with an error.");
  }

  void
  ImplicitParameters::parse_parameters(ParameterHandler &prm)
  {
    tolerance          = prm.get_double("Tolerance");
    absolute_tolerance = prm.get_double("Absolute tolerance");
    max_newton         = prm.get_integer("Maximum Newton iterations");
    line_search        = prm.get_bool("Line search");
    linear_solver      = prm.get("Linear solver");
    preconditioner     = prm.get("Preconditioner");
    aggregation_threshold = prm.get_double("AMG aggregation threshold");
    linear_tolerance   = prm.get_double("Linear tolerance");
    max_linear         = prm.get_integer("Maximum linear iterations");
    tangent            = prm.get("Tangent");
    jacobian           = prm.get("Jacobian");
    keep_tangent_contraction = prm.get_double("Keep tangent below contraction");
    AssertThrow(jacobian == "Assembled" || tangent == "Analytic",
                ExcMessage("Solver/Implicit/Jacobian = Matrix free needs Tangent = Analytic (its "
                           "preconditioner is the analytic tangent's diagonal)"));
    max_damage_solves  = prm.get_integer("Maximum damage solves");
    adaptive_steps     = prm.get_bool("Adaptive steps");
    min_step_fraction  = prm.get_double("Minimum step fraction");
    AssertThrow(!adaptive_steps || min_step_fraction > 0,
                ExcMessage("Solver/Implicit/Minimum step fraction must be positive with Adaptive steps: the "
                           "sub-steps of a step that keeps failing would never end"));
    AssertThrow(tolerance > 0 || absolute_tolerance > 0,
                ExcMessage("Solver/Implicit/Tolerance and Absolute tolerance are both 0: Newton would never stop"));
    // Both are relative: at 1 or more Newton accepts the initial guess (no
    // solve, exit 0 with the loads unbalanced), and the Krylov solver returns
    // du = 0 (Newton then "stagnates", blamed on the tangent).
    AssertThrow(tolerance < 1,
                ExcMessage("Solver/Implicit/Tolerance must be below 1, got " + Utilities::to_string(tolerance) +
                           ": it is relative to the forces, and at 1 or more Newton accepts the initial guess "
                           "without solving (e.g. 1e-8; Absolute tolerance is the one in force units)"));
    AssertThrow(linear_tolerance < 1,
                ExcMessage("Solver/Implicit/Linear tolerance must be below 1, got " +
                           Utilities::to_string(linear_tolerance) +
                           ": it is relative to |R|, and at 1 or more the Krylov solver returns a zero "
                           "Newton step (e.g. 1e-10)"));
  }
} // namespace perideal
