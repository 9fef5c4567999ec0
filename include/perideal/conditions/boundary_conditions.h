#pragma once
// Initial and boundary conditions on regions, each a muparser expression in
// x, y, z and t for one component (Peridigm's "Boundary Conditions" section).
// The points of a condition are found once at set-up; a value that does not
// depend on t is evaluated once.

#include <perideal/base/expression.h>
#include <perideal/base/input.h>
#include <perideal/discretization/point_cloud.h>

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
      body_force,
      traction
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
    /// A load added to the force: body force or traction.
    bool
    is_load() const
    {
      return type == Type::body_force || type == Type::traction;
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
    int                         boundary_id = -1; // traction: faces with this id; -1: by region
    std::unique_ptr<Expression> value;

    /// The owned DoFs of this component in the region (MechanicalState's
    /// numbering: point entries, virtual points excluded, and FE DoFs), set
    /// by the core.
    std::vector<unsigned int> dofs;
    /// Traction: owned boundary faces of FE cells (cell, face number).
    std::vector<std::pair<CellIterator, unsigned int>> faces;
    /// Traction: owned boundary faces of PD cells, each loading its cell's
    /// point with traction x area (as a body force over the point's volume).
    struct PointFace
    {
      unsigned int      point; // the point's local index
      double            area;
      dealii::Point<dim> center;
    };
    std::vector<PointFace> point_faces;
    bool                   on_points = false; // point_faces on some rank
  };
} // namespace perideal
