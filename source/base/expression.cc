#include <perideal/base/expression.h>
#include <perideal/base/time_function.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>

#include <muParser.h>

#include <cmath>
#include <sstream>

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
    , variable_names(variables)
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
        // A key of fewer variables (e.g. t alone) says which it takes.
        std::string allowed;
        if (variables != std::vector<std::string>{"x", "y", "z", "t"})
          for (unsigned int v = 0; v < variables.size(); ++v)
            allowed += (v == 0 ? " (the key's variables: " : ", ") + variables[v] + (v + 1 == variables.size() ? ")" : "");
        AssertThrow(false,
                    dealii::ExcMessage(where + ": cannot parse the expression '" +
                                       expression + "': " + e.GetMsg() + allowed));
      }
  }

  TimeFunction::TimeFunction(const std::string &text, const std::string &where)
    : expression(dealii::Utilities::trim(text), where, 0, {"t"})
  {}

  double
  TimeFunction::operator()(const double t) const
  {
    return expression.value(dealii::Point<3>(t, 0, 0), t); // t is bound to the first variable
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
        const double result = parser->Eval();
        if (!std::isfinite(result) && !first_nonfinite.any)
          first_nonfinite = {true, result, x, t};
        return result;
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

  std::string
  Expression::nonfinite_message() const
  {
    std::ostringstream m;
    m.precision(6);
    m << where << ": '" << expression << "' is not finite at ";
    const double at[4] = {first_nonfinite.x[0], first_nonfinite.x[1], first_nonfinite.x[2], first_nonfinite.t};
    for (unsigned int v = 0; v < variable_names.size() && v < 4; ++v)
      m << (v > 0 ? ", " : "") << variable_names[v] << " = " << at[v];
    m << " (it gives " << first_nonfinite.value << ")";
    return m.str();
  }

  void
  check_finite(const std::vector<const Expression *> &expressions, const MPI_Comm comm)
  {
    unsigned int first = expressions.size();
    for (unsigned int e = 0; e < expressions.size() && first == expressions.size(); ++e)
      if (expressions[e] != nullptr && expressions[e]->gave_nonfinite())
        first = e;
    const unsigned int bad = dealii::Utilities::MPI::min(first, comm);
    if (bad == expressions.size())
      return;
    // The lowest rank that saw it names the point, on every rank.
    const unsigned int rank  = dealii::Utilities::MPI::this_mpi_process(comm);
    const unsigned int owner = dealii::Utilities::MPI::min(first == bad ? rank : dealii::numbers::invalid_unsigned_int, comm);
    const std::string  message =
      dealii::Utilities::MPI::broadcast(comm, rank == owner ? expressions[bad]->nonfinite_message() : std::string(), owner);
    AssertThrow(false, dealii::ExcMessage(message));
  }
} // namespace perideal
