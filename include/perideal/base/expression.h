#pragma once
// A muparser expression in x, y, z and t, as in Peridigm's input decks.
// Besides muparser's built-ins it knows atan2(y,x), pow(a,b), floor, ceil and
// rnd(a): a uniform random number in [-a, a]. rnd draws from a hash of the
// point's rank-independent key, the seed and the call's position in the
// expression, so the same point gets the same number on any number of ranks.

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mu
{
  class Parser;
}

namespace perideal
{
  class Expression
  {
  public:
    /// @p where names the key in error messages, e.g. "Boundary conditions/vx/Value".
    /// @p variables names the (at most four) variables, bound in order to
    /// x[0], x[1], x[2] and t of value().
    Expression(const std::string              &expression,
               const std::string              &where,
               const std::uint64_t             seed      = 0,
               const std::vector<std::string> &variables = {"x", "y", "z", "t"});
    ~Expression();
    Expression(Expression &&) noexcept;

    double
    value(const dealii::Point<3> &x,
          const double            t,
          const std::uint64_t     point_key = 0) const;

    /// Whether the expression reads t (if not, values can be computed once).
    bool
    depends_on_time() const;

    /// Whether value() has returned a value that is not finite (NaN, inf)
    /// on this rank; the first such evaluation is kept for the message.
    bool
    gave_nonfinite() const
    {
      return first_nonfinite.any;
    }

    /// "where: 'text' is not finite at x = .., y = .., z = .., t = .. (it gives nan)"
    /// for the first non-finite value seen on this rank.
    std::string
    nonfinite_message() const;

    const std::string &
    text() const
    {
      return expression;
    }

    /// The key it was read from, e.g. "Boundary conditions/vx/Value".
    const std::string &
    key() const
    {
      return where;
    }

  private:
    std::string                expression;
    std::string                where;
    std::uint64_t              seed;
    std::unique_ptr<mu::Parser> parser;
    std::unique_ptr<double[]>  vars; // x, y, z, t (stable addresses for muparser)
    bool                       uses_t = false;
    std::vector<std::string>   variable_names;
    struct NonFinite
    {
      bool             any = false;
      double           value = 0;
      dealii::Point<3> x;
      double           t = 0;
    };
    mutable NonFinite first_nonfinite;
  };

  /// Collective over @p comm: if one of @p expressions has given a value that
  /// is not finite on some rank, throws ExcMessage naming the first such
  /// expression of the list, its text and the point (the lowest such rank's
  /// first). User expressions are evaluated over each rank's own points, so
  /// the check must be collective to stop every rank alike.
  void
  check_finite(const std::vector<const Expression *> &expressions, const MPI_Comm comm);

  /// splitmix64: a fast, well-mixed 64-bit hash.
  std::uint64_t
  mix64(std::uint64_t z);
} // namespace perideal
