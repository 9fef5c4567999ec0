#pragma once
// A global quantity over a region, written as a column of the globals CSV
// (Peridigm's Node_Set_Data computes): the sum, volume-weighted mean, minimum
// or maximum of a displacement, force or reference-position component, the
// damage or the largest bond stretch over the region's points.
// With a Reference expression it takes |q - reference(x, t)|: errors against
// analytic solutions (patch tests, verification).
// With Rate it also writes NAME_rate, the value's rate of change over the
// globals rows of the last Rate window (a crack tip's speed, a reaction's rate).
// Reaction forces, virtual strain gauges (the difference of two region means
// of the displacement over the difference of their mean positions) and probes
// are built from it. The variable is a PointQuantity, the operation a
// Reduction, each chosen by name from its registry.

#include <perideal/base/expression.h>
#include <perideal/base/input.h>
#include <perideal/compute/point_quantity.h>
#include <perideal/compute/reduction.h>

#include <deal.II/base/mpi.h>

#include <deque>
#include <memory>
#include <string>
#include <vector>

namespace perideal
{
  class CheckpointWriter;
  class CheckpointReader;
  class RegionCompute
  {
  public:
    /// Variable and Operation name a PointQuantity and a Reduction of their registries.
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm, const std::string &path);

    /// The operation over the owned points (and, in runs with continuum
    /// blocks, FE nodes) of this compute's region of the variable at @p time
    /// (|q - reference| with a Reference). Collective.
    double
    evaluate(const ComputeData &data, const double time, const MPI_Comm comm) const;

    /// The rate of change of the value @p value now at @p time: the slope
    /// between this globals row and the one before (Rate window = 0) or the
    /// least-squares slope over the rows of the last Rate window; 0 at the
    /// first row. Records the row, so call it once per globals row.
    double
    rate_of(const double value, const double time);

    /// Whether an FE DoF of component @p c enters the compute.
    bool
    uses_node(const unsigned int c) const
    {
      return quantity->at_node(c);
    }

    std::string               name, region, variable, operation;
    std::shared_ptr<const Expression> reference; // none: the variable itself
    bool                      rate        = false; // also the column NAME_rate
    double                    rate_window = 0;
    std::vector<unsigned int> points;        // owned points in the region
    std::vector<unsigned int> nodes;         // owned FE DoFs in the region it uses (continuum blocks)

    /// rate_of()'s rows (checkpoint.h).
    void
    save(CheckpointWriter &out) const;
    void
    load(CheckpointReader &in);

  private:
    std::unique_ptr<PointQuantity> quantity;
    std::unique_ptr<Reduction>     reduction;
    // (time, value) of the globals rows rate_of() has seen, as far back as
    // the window reaches (the row before, without a window).
    std::deque<std::pair<double, double>> history;
  };
} // namespace perideal
