#pragma once
// The operations a compute applies over its region (Computes/NAME/Operation):
// values per point (and FE node) in, one global number out. Each is a plugin
// registered with PERIDEAL_REGISTER(Reduction, Class, "Name", "doc") (the
// built-in ones: source/compute/reductions.cc), so a new operation is one
// registration.

#include <perideal/base/input.h>
#include <perideal/base/registry.h>

#include <deal.II/base/mpi.h>

#include <vector>

namespace perideal
{
  class Reduction
  {
  public:
    /// A reduction has no keys of its own.
    static void
    declare_parameters(ParameterHandler &)
    {}

    virtual ~Reduction() = default;

    /// The result over all ranks of this rank's values @p q with their
    /// volumes @p V (the region's points, then its FE nodes). Collective.
    virtual double
    reduce(const std::vector<double> &q, const std::vector<double> &V, const MPI_Comm comm) const = 0;
  };
} // namespace perideal
