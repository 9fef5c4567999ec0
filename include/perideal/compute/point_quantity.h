#pragma once
// The quantities a compute can take over a region (Computes/NAME/Variable):
// a value per point and, where defined, per FE node of a continuum block.
// Each is a plugin registered with PERIDEAL_REGISTER(PointQuantity, Class,
// "Name", "doc") (the built-in ones: source/compute/point_quantities.cc), so
// a new quantity is one registration.

#include <perideal/base/input.h>
#include <perideal/base/registry.h>
#include <perideal/discretization/point_cloud.h>
#include <perideal/model/state.h>
#include <perideal/neighborhood/bonds.h>

#include <string>
#include <vector>

namespace perideal
{
  class ForceModel;
  class ContinuumField;

  /// What a compute's quantity or an output field (output_field.h) reads,
  /// at the time of the output step.
  struct ComputeData
  {
    const PointCloud          &cloud;
    const Bonds               &bonds;
    const MechanicalState     &state;
    const ForceModel          &model;
    const ContinuumField      *continuum;    // nullptr without continuum blocks
    const std::vector<double> *node_density; // per FE node of continuum; with it
    unsigned int               rank;         // this process's in the run's communicator
    // Per owned point its fragment's number (compute/fragments.h); only at
    // field steps that write fragments, else nullptr.
    const std::vector<double> *fragment = nullptr;
  };

  class PointQuantity
  {
  public:
    /// Most quantities have no keys of their own. Those that do (Crack tip)
    /// declare them in every compute's section, documented as theirs.
    static void
    declare_parameters(ParameterHandler &)
    {}

    virtual ~PointQuantity() = default;

    /// Reads the quantity's own keys of the compute's section @p path.
    virtual void
    parse_parameters(ParameterHandler &, const std::string & /*path*/)
    {}

    /// The value at owned point @p i.
    virtual double
    value(const ComputeData &data, const unsigned int i) const = 0;

    /// Whether the quantity is defined at the FE DoFs of component @p c (the
    /// region's FE nodes of that component then enter the compute).
    virtual bool
    at_node(const unsigned int) const
    {
      return false;
    }

    /// The value at FE node @p k of data.continuum->nodes (if at_node).
    virtual double
    node_value(const ComputeData &, const unsigned int) const
    {
      return 0;
    }
  };
} // namespace perideal
