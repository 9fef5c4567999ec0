#pragma once
// The fields of the field files (Output/Variables). The core's are plugins
// registered with PERIDEAL_REGISTER(OutputField, Class, "Name", "doc") (the
// built-in ones: source/output/output_fields.cc); the models' are the point
// fields they give an output name (PointField::output_name). Output/Variables'
// valid names and documentation, and what Postprocess writes, come from
// output_variables(), so a new field is one registration.

#include <perideal/base/registry.h>
#include <perideal/compute/point_quantity.h>
#include <perideal/material/field_store.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace perideal
{
  class OutputField
  {
  public:
    /// A field has no keys of its own.
    static void
    declare_parameters(ParameterHandler &)
    {}

    virtual ~OutputField() = default;

    /// 1: a scalar; 3: a vector; 6: a symmetric 3x3 tensor (xx yy zz xy yz
    /// xz, written as 9 components); 9: a 3x3 tensor, row-major.
    virtual unsigned int
    n_components() const = 0;

    /// True for a vector of the mechanical state, written per point on the
    /// PD cells and per FE node (node_value()) on the continuum cells; false
    /// for a field written as cell data, constant per point.
    virtual bool
    nodal() const
    {
      return false;
    }

    /// Where the field stands in Output/Variables and in the files
    /// (ascending; the models' fields stand at model_fields_position). The
    /// files list the fields in this order, so it is part of their format.
    virtual int
    position() const = 0;

    /// Component @p c of the value at owned point @p i (a PD point, or a
    /// virtual point if at_virtual_points()).
    virtual double
    value(const ComputeData &data, const unsigned int i, const unsigned int c) const = 0;

    /// A nodal vector's value at FE node @p k of data.continuum->nodes (the
    /// component nodes[k].component); continuum blocks only.
    virtual double
    node_value(const ComputeData &, const unsigned int) const
    {
      return 0;
    }

    /// Whether a scalar field also has a value at the virtual points, on
    /// the continuum cells that hold them.
    virtual bool
    at_virtual_points() const
    {
      return false;
    }
  };

  /// The position() of the models' fields: after Damage, before Number of neighbors.
  constexpr int model_fields_position = 60;

  /// One of Output/Variables.
  struct OutputVariable
  {
    std::string                  name, documentation;
    std::unique_ptr<OutputField> field;
  };

  /// Every field a run can write: the registered ones and the models'
  /// (@p model_fields: model_output_fields()), ordered by position(); the
  /// models' in their given order.
  std::vector<OutputVariable>
  output_variables(const std::vector<PointField> &model_fields);
} // namespace perideal
