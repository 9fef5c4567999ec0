#pragma once
// Where a run that blows up went wrong: the first point (or FE DoF) with a
// non-finite value, and the fastest one, the same on any number of ranks.

#include <perideal/base/best_point.h>
#include <perideal/solver/time_integrator.h>

#include <string>

namespace perideal
{
  class StabilityGuard
  {
  public:
    explicit StabilityGuard(const SimulatorAccess &access)
      : access(access)
    {}

    /// "point N at (x, y, z)": the first point (smallest global id; then FE
    /// DoFs) with a non-finite displacement, velocity or force; or, if all
    /// are finite, the fastest point (the kinetic energy overflows). Collective.
    std::string
    locate_nonfinite() const;
    /// The point (or FE DoF) with the largest speed (the value). Collective.
    BestPoint
    fastest_point() const;

  private:
    const SimulatorAccess &access;
  };
} // namespace perideal
