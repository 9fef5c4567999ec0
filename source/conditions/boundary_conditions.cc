#include <perideal/conditions/boundary_conditions.h>

#include <deal.II/base/utilities.h>

namespace perideal
{
  using namespace dealii;

  void
  BoundaryCondition::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Type", "Initial velocity",
                      Patterns::Selection("Initial displacement|Initial velocity|"
                                          "Prescribed displacement|Prescribed velocity|Body force|Traction"),
                      "Initial displacement/velocity: set at the initial time. "
                      "Prescribed displacement/velocity: imposed on the component at "
                      "every step (Dirichlet). Body force: force per unit volume added "
                      "to the component. Traction: force per unit area on the boundary "
                      "faces whose centre lies in Region (or, with Boundary id, that "
                      "carry this id), evaluated at the face centre: on a continuum "
                      "cell's face integrated against its shape functions, on a "
                      "peridynamic cell's face the force traction x face area on the "
                      "cell's point (a body force over its volume), so the load stays "
                      "when Adaptivity converts the cell.");
    prm.declare_entry("Region", "All", Patterns::Anything(),
                      "The name of a region of Discretization/Regions, or All.");
    prm.declare_entry("Boundary id", "-1", Patterns::Integer(-1),
                      "Traction only: the boundary id of the faces (Gmsh surface physical "
                      "groups); -1: the faces in Region.");
    prm.declare_entry("Component", "x", Patterns::Selection("x|y|z"),
                      "The component the value applies to (Peridigm's 'Coordinate').");
    prm.declare_entry("Value", "0", Patterns::Anything(),
                      "muparser expression in x, y, z (reference position) and t. "
                      "rnd(a) adds a uniform random number in [-a, a], the same for a "
                      "point on any number of ranks; atan2, pow, floor and ceil are known.");
    prm.declare_entry("Random seed", "0", Patterns::Integer(0),
                      "Seed of rnd() in Value. The numbers depend on the seed, the "
                      "component and the point, not on the number of ranks.");
  }

  void
  BoundaryCondition::parse_parameters(ParameterHandler &prm, const std::string &path)
  {
    const std::string t = prm.get("Type");
    type                = t == "Initial displacement"    ? Type::initial_displacement :
                          t == "Initial velocity"        ? Type::initial_velocity :
                          t == "Prescribed displacement" ? Type::prescribed_displacement :
                          t == "Prescribed velocity"     ? Type::prescribed_velocity :
                          t == "Traction"                ? Type::traction :
                                                           Type::body_force;
    boundary_id = prm.get_integer("Boundary id");
    region    = prm.get("Region");
    // Only a Traction reads Boundary id: elsewhere it was silently ignored,
    // and the condition acted on all of Region instead.
    AssertThrow(boundary_id < 0 || type == Type::traction,
                ExcMessage(path + "/Boundary id: only a Traction selects faces by boundary id; this " + t +
                           " acts on the points of Region ('" + region + "'), so Boundary id " +
                           std::to_string(boundary_id) + " would be ignored: remove it and select the points "
                           "with a region (Discretization/Regions, Type = Physical group, Physical group "
                           "dimension = 2 for a Gmsh surface group)"));
    AssertThrow(boundary_id < 0 || region == "All",
                ExcMessage(path + ": Boundary id " + std::to_string(boundary_id) + " and Region '" + region +
                           "' both select the faces of this Traction, and Region would be ignored: give one "
                           "of them (Region = All, or Boundary id = -1)"));
    component = prm.get("Component")[0] - 'x';
    // The component enters the seed: x, y and z conditions with the same seed
    // still draw independent numbers at a point.
    value = std::make_unique<Expression>(prm.get("Value"),
                                         path + "/Value",
                                         dim * prm.get_integer("Random seed") + component);
  }
} // namespace perideal
