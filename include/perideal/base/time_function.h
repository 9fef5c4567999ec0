#pragma once
// A key that is a function of the time t alone: a time dependent critical
// stretch, spring constant, ... One value acts everywhere at a time, so an
// expression naming x, y or z is refused where it is read (naming the key and
// its only variable t) instead of being evaluated at x = y = z = 0.

#include <perideal/base/expression.h>

#include <string>

namespace perideal
{
  class TimeFunction
  {
  public:
    /// @p where names the key in error messages, e.g. "Contact models/springs/Spring constant".
    TimeFunction(const std::string &text, const std::string &where);

    double
    operator()(const double t) const;

    const std::string &
    text() const
    {
      return expression.text();
    }

  private:
    Expression expression;
  };
} // namespace perideal
