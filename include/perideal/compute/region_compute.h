#pragma once
// A global quantity over a region, written as a column of the globals CSV
// (Peridigm's Node_Set_Data computes): the sum, volume-weighted mean, minimum
// or maximum of a displacement, force or reference-position component, the
// damage or the largest bond stretch over the region's points.
// Reaction forces, virtual strain gauges (the difference of two region means
// of the displacement over the difference of their mean positions) and probes
// are built from it.

#include <perideal/base/input.h>

#include <deal.II/base/mpi.h>

#include <functional>
#include <string>
#include <vector>

namespace perideal
{
  class RegionCompute
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm, const std::string &path);

    /// The value over points (owned, of this compute's region) of @p value(i,
    /// component); @p volume per point. Collective.
    double
    evaluate(const std::function<double(unsigned int)> &value,
             const std::vector<double>                 &volume,
             const MPI_Comm                             comm) const;

    std::string               name, region, variable, operation;
    unsigned int              component = 0; // for vector variables
    std::vector<unsigned int> points;        // owned points in the region
  };
} // namespace perideal
