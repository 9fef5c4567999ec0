// Region Type = Expression: the points where a muparser expression in x, y, z
// is non-zero.
#include <perideal/geometry/region.h>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class ExpressionRegion : public RegionSelector
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Expression", "1", Patterns::Anything(), "Expression: muparser expression in x, y, z; non-zero means inside, e.g. 'x < 0.01 && y > 0'.");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path, const SceneGeometry &) override
      {
        expression = std::make_unique<Expression>(prm.get("Expression"), path + "/Expression");
      }

      bool
      contains(const Point<dim> &x, const DoFHandler<dim>::active_cell_iterator &) const override
      {
        return expression->value(x, 0) != 0;
      }

      const Expression *
      user_expression() const override
      {
        return expression.get();
      }

    private:
      std::unique_ptr<Expression> expression;
    };
  } // namespace

  PERIDEAL_REGISTER(RegionSelector, ExpressionRegion, "Expression",
                    "a point is in an Expression region where the expression in x, y, z is non-zero.")
} // namespace perideal
