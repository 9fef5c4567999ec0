#pragma once
// A global quantity over a region, written as a column of the globals CSV
// (Peridigm's Node_Set_Data computes): the sum, volume-weighted mean, minimum
// or maximum of a displacement, force or reference-position component, the
// damage or the largest bond stretch over the region's points.
// With a Reference expression it takes |q - reference(x, t)|: errors against
// analytic solutions (patch tests, verification).
// Reaction forces, virtual strain gauges (the difference of two region means
// of the displacement over the difference of their mean positions) and probes
// are built from it.

#include <perideal/base/expression.h>
#include <perideal/base/input.h>

#include <deal.II/base/mpi.h>

#include <functional>
#include <memory>
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
    /// component); @p volume per point; and, in runs with continuum blocks,
    /// over the FE nodes of the region, @p node_value(k) with @p node_volume(k)
    /// (the lumped volume, for Mean). Collective.
    double
    evaluate(const std::function<double(unsigned int)> &value,
             const std::vector<double>                 &volume,
             const MPI_Comm                             comm,
             const std::function<double(unsigned int)> &node_value  = {},
             const std::function<double(unsigned int)> &node_volume = {}) const;

    /// Whether an FE DoF of component @p c enters the compute (its variable
    /// is defined at FE nodes: displacement, force, position per component,
    /// kinetic energy over all).
    bool
    uses_node(const unsigned int c) const
    {
      return variable == "Kinetic energy" ||
             (variable.size() > 2 && variable[variable.size() - 2] == ' ' && c == component);
    }

    std::string               name, region, variable, operation;
    std::shared_ptr<const Expression> reference; // none: the variable itself
    unsigned int              component = 0; // for vector variables
    std::vector<unsigned int> points;        // owned points in the region
    std::vector<unsigned int> nodes;         // owned FE DoFs in the region it uses (continuum blocks)
  };
} // namespace perideal
