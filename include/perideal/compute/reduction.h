#pragma once
// The operations a compute applies over its region (Computes/NAME/Operation):
// values per point (and FE node) in, one global number out. Each is a plugin
// registered with PERIDEAL_REGISTER(Reduction, Class, "Name", "doc") (the
// built-in ones: source/compute/reductions.cc), so a new operation is one
// registration.

#include <perideal/base/input.h>
#include <perideal/base/registry.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>

#include <string>
#include <vector>

namespace perideal
{
  class Reduction
  {
  public:
    /// Most reductions have no keys of their own. Those that do (Nearest
    /// point) declare them in every compute's section, documented as theirs.
    static void
    declare_parameters(ParameterHandler &)
    {}

    virtual ~Reduction() = default;

    /// Reads the reduction's own keys of the compute's section @p path.
    virtual void
    parse_parameters(ParameterHandler &, const std::string & /*path*/)
    {}

    /// Whether reduce() needs the reference positions of the values.
    virtual bool
    needs_positions() const
    {
      return false;
    }

    /// The result over all ranks of this rank's values @p q with their
    /// volumes @p V and, if needs_positions(), their reference positions
    /// @p x (else empty): the region's points, then its FE nodes. Collective.
    virtual double
    reduce(const std::vector<double> &q, const std::vector<double> &V, const std::vector<dealii::Point<3>> &x,
           const MPI_Comm comm) const = 0;
  };
} // namespace perideal
