#include <perideal/base/expression.h>

#include <deal.II/base/exceptions.h>

#include <muParser.h>

#include <cmath>

namespace perideal
{
  std::uint64_t
  mix64(std::uint64_t z)
  {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

  namespace
  {
    // muparser callbacks are plain functions; rnd() reads the point being
    // evaluated from here. Evaluation is single threaded.
    struct RandomState
    {
      std::uint64_t key   = 0;
      std::uint64_t calls = 0;
    };
    RandomState random_state;

    double
    rnd(const double amplitude)
    {
      const std::uint64_t h =
        mix64(random_state.key ^ mix64(++random_state.calls));
      const double u = (h >> 11) * 0x1.0p-53; // [0, 1)
      return amplitude * (2 * u - 1);
    }
    double
    atan2_(const double y, const double x)
    {
      return std::atan2(y, x);
    }
    double
    pow_(const double a, const double b)
    {
      return std::pow(a, b);
    }
    double
    floor_(const double a)
    {
      return std::floor(a);
    }
    double
    ceil_(const double a)
    {
      return std::ceil(a);
    }
  } // namespace

  Expression::Expression(const std::string              &expression_,
                         const std::string              &where_,
                         const std::uint64_t             seed_,
                         const std::vector<std::string> &variables)
    : expression(expression_)
    , where(where_)
    , seed(seed_)
    , parser(std::make_unique<mu::Parser>())
    , vars(new double[4]{0, 0, 0, 0})
  {
    AssertThrow(!expression.empty(),
                dealii::ExcMessage(where + ": the expression is empty"));
    try
      {
        for (unsigned int v = 0; v < variables.size() && v < 4; ++v)
          parser->DefineVar(variables[v], &vars[v]);
        parser->DefineConst("pi", M_PI);
        parser->DefineFun("rnd", rnd, false);
        parser->DefineFun("atan2", atan2_);
        parser->DefineFun("pow", pow_);
        parser->DefineFun("floor", floor_);
        parser->DefineFun("ceil", ceil_);
        parser->SetExpr(expression);
        parser->Eval(); // muparser parses lazily: force it now
        for (const auto &v : parser->GetUsedVar())
          if (variables.size() == 4 && v.first == variables[3])
            uses_t = true;
      }
    catch (const mu::Parser::exception_type &e)
      {
        AssertThrow(false,
                    dealii::ExcMessage(where + ": cannot parse the expression '" +
                                       expression + "': " + e.GetMsg()));
      }
  }

  Expression::~Expression() = default;
  Expression::Expression(Expression &&) noexcept = default;

  double
  Expression::value(const dealii::Point<3> &x,
                    const double            t,
                    const std::uint64_t     point_key) const
  {
    vars[0]            = x[0];
    vars[1]            = x[1];
    vars[2]            = x[2];
    vars[3]            = t;
    random_state.key   = mix64(point_key ^ mix64(seed));
    random_state.calls = 0;
    try
      {
        return parser->Eval();
      }
    catch (const mu::Parser::exception_type &e)
      {
        AssertThrow(false,
                    dealii::ExcMessage(where + ": cannot evaluate '" +
                                       expression + "': " + e.GetMsg()));
      }
    return 0;
  }

  bool
  Expression::depends_on_time() const
  {
    return uses_t;
  }
} // namespace perideal
