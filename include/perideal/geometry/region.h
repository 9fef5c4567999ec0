#pragma once
// A named region (Peridigm's node set): the points of a run that boundary
// conditions and blocks act on, chosen once at set-up by a selector of
// Registry<RegionSelector> named by its Type (All, Box, Expression, Physical
// group, Node set, Side set, Element block: source/geometry/region_*.cc).

#include <perideal/base/expression.h>
#include <perideal/base/input.h>
#include <perideal/base/registry.h>
#include <perideal/geometry/scene.h>

#include <deal.II/base/point.h>
#include <deal.II/dofs/dof_handler.h>

#include <memory>
#include <string>

namespace perideal
{
  /// How a region chooses its points: a plugin registered with
  /// PERIDEAL_REGISTER(RegionSelector, Class, "Type", "doc"), whose static
  /// declare_parameters declares its keys in the region's subsection (every
  /// type's keys are declared there; key names are shared by all types).
  class RegionSelector
  {
  public:
    virtual ~RegionSelector() = default;

    /// Reads the keys of the region's subsection; @p path names it in errors,
    /// @p geometry is the scene's (its mesh sets).
    virtual void
    parse_parameters(ParameterHandler &prm, const std::string &path, const SceneGeometry &geometry) = 0;

    /// Whether the point @p x (a cell centroid or node) of @p cell is inside.
    virtual bool
    contains(const dealii::Point<dim> &x, const dealii::DoFHandler<dim>::active_cell_iterator &cell) const = 0;

    /// The user's expression, if the selector has one, for the collective
    /// check of its values (check_finite()).
    virtual const Expression *
    user_expression() const
    {
      return nullptr;
    }
  };

  class Region
  {
  public:
    /// Declared inside the region's own subsection.
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm, const std::string &path, const SceneGeometry &geometry);

    bool
    contains(const dealii::Point<dim>                               &x,
             const dealii::DoFHandler<dim>::active_cell_iterator &cell) const
    {
      return selector->contains(x, cell);
    }

    /// The expression of an Expression region (nullptr otherwise).
    const Expression *
    user_expression() const
    {
      return selector->user_expression();
    }

    std::string name;

  private:
    std::unique_ptr<RegionSelector> selector;
  };
} // namespace perideal
