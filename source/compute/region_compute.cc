#include <perideal/compute/region_compute.h>

#include <perideal/continuum/continuum_field.h>

#include <cmath>

namespace perideal
{
  using namespace dealii;

  void
  RegionCompute::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Region", "All", Patterns::Anything(),
                      "Name of a region of Discretization/Regions, or All. It must hold at least one point "
                      "(or FE node): over nothing a compute has no value, and the run stops.");
    prm.declare_entry("Variable", "Displacement x", Registry<PointQuantity>::instance().selection(),
                      Registry<PointQuantity>::instance().documentation() +
                        " In continuum blocks the FE nodes of the region count too: their displacement, their "
                        "nodal force (internal plus body force), their position, 1/2 M v^2 with the lumped "
                        "mass; damage and bond stretch are defined at PD points only.");
    prm.declare_entry("Operation", "Sum", Registry<Reduction>::instance().selection(),
                      Registry<Reduction>::instance().documentation());
    prm.declare_entry("Reference", "", Patterns::Anything(),
                      "An expression in x, y, z (the reference position of the point or FE node) and t. "
                      "If set, the compute takes |q - reference| instead of q: the error against an "
                      "analytic solution, e.g. Variable = Displacement x, Reference = 1e-3*x, Operation "
                      "= Maximum for the largest error of a patch test.");
  }

  void
  RegionCompute::parse_parameters(ParameterHandler &prm, const std::string &path)
  {
    region    = prm.get("Region");
    variable  = prm.get("Variable");
    operation = prm.get("Operation");
    reference.reset();
    if (!prm.get("Reference").empty())
      reference = std::make_shared<Expression>(prm.get("Reference"), path + "/Reference");
    quantity  = Registry<PointQuantity>::instance().create(variable, path + "/Variable");
    reduction = Registry<Reduction>::instance().create(operation, path + "/Operation");
  }

  double
  RegionCompute::evaluate(const ComputeData &data, const double time, const MPI_Comm comm) const
  {
    std::vector<double> q, V;
    q.reserve(points.size() + nodes.size());
    V.reserve(points.size() + nodes.size());
    for (const unsigned int i : points)
      {
        const double value = quantity->value(data, i);
        q.push_back(reference ? std::abs(value - reference->value(data.cloud.position(i), time)) : value);
        V.push_back(data.cloud.volume[i]);
      }
    for (const unsigned int k : nodes)
      {
        // The lumped volume, for Mean: the node's lumped mass over its block's density.
        const auto  &node  = data.continuum->nodes[k];
        const double value = quantity->node_value(data, k);
        q.push_back(reference ? std::abs(value - reference->value(node.x, time)) : value);
        V.push_back(data.continuum->mass.local_element(node.local) / (*data.node_density)[k]);
      }
    return reduction->reduce(q, V, comm);
  }
} // namespace perideal
