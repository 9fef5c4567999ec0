#pragma once
// Initial and boundary conditions on regions, each a muparser expression in
// x, y, z and t for one component (Peridigm's "Boundary Conditions" section).
// The points of a condition are found once at set-up; a value that does not
// depend on t is evaluated once.

#include <perideal/base/expression.h>
#include <perideal/base/input.h>

#include <memory>
#include <string>
#include <vector>

namespace perideal
{
  class BoundaryCondition
  {
  public:
    enum class Type
    {
      initial_displacement,
      initial_velocity,
      prescribed_displacement,
      prescribed_velocity,
      body_force
    };

    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm, const std::string &path);

    bool
    is_initial() const
    {
      return type == Type::initial_displacement || type == Type::initial_velocity;
    }
    bool
    is_prescribed() const
    {
      return type == Type::prescribed_displacement || type == Type::prescribed_velocity;
    }

    std::string                 name;
    Type                        type = Type::initial_velocity;
    std::string                 region;
    unsigned int                component = 0;
    std::unique_ptr<Expression> value;

    /// Owned points of the region, set by the core (virtual points excluded).
    std::vector<unsigned int> points;
    /// Owned FE DoFs of this component in the region (indices into
    /// ContinuumField::nodes), set by the core in runs with continuum blocks.
    std::vector<unsigned int> nodes;
  };
} // namespace perideal
