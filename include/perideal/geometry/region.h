#pragma once
// A named region (Peridigm's node set): the points of a run that boundary
// conditions and blocks act on, chosen once at set-up by a bounding box, a
// muparser expression in x, y, z (non-zero = inside), or a Gmsh physical group.

#include <perideal/base/expression.h>
#include <perideal/base/input.h>

#include <deal.II/base/point.h>
#include <deal.II/dofs/dof_handler.h>

#include <memory>
#include <string>

namespace perideal
{
  class Region
  {
  public:
    /// Declared inside the region's own subsection.
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm, const std::string &path);

    bool
    contains(const dealii::Point<dim>                               &x,
             const dealii::DoFHandler<dim>::active_cell_iterator &cell) const;

    /// The expression of an Expression region (nullptr otherwise), for the
    /// collective check of its values (check_finite()).
    const Expression *
    user_expression() const
    {
      return expression.get();
    }

    std::string name;

  private:
    std::string                 type;
    dealii::Point<dim>          lower, upper;
    std::unique_ptr<Expression> expression;
    unsigned int                group_id = 0, group_dimension = 3;
  };
} // namespace perideal
