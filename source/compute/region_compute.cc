#include <perideal/compute/region_compute.h>

#include <algorithm>
#include <limits>

namespace perideal
{
  using namespace dealii;

  void
  RegionCompute::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Region", "All", Patterns::Anything(),
                      "Name of a region of Discretization/Regions, or All. It must hold at least one point "
                      "(or FE node): over nothing a compute has no value, and the run stops.");
    prm.declare_entry("Variable", "Displacement x",
                      Patterns::Selection("Displacement x|Displacement y|Displacement z|Force x|Force y|Force z|"
                                        "Position x|Position y|Position z|Damage|Bond stretch|Kinetic energy"),
                      "Displacement: of a point. Force: the force on a point, V f (force density times "
                      "volume), internal plus body force; its sum over a region of prescribed points is "
                      "minus the reaction there. Position: the reference position of a point (with "
                      "Mean: where a region's mean displacement is taken, e.g. for the length of a "
                      "virtual strain gauge). Damage: point damage. Bond stretch: the largest stretch "
                      "(|y| - |xi|)/|xi| of a point's intact bonds (with Maximum: how close the region "
                      "is to a critical stretch). Kinetic energy: 1/2 rho V |v|^2 of a point. In continuum "
                      "blocks the FE nodes of the region count too: their displacement, their nodal force "
                      "(internal plus body force), their position, 1/2 M v^2 with the lumped mass; damage "
                      "and bond stretch are defined at PD points only.");
    prm.declare_entry("Operation", "Sum", Patterns::Selection("Sum|Mean|Minimum|Maximum"),
                      "Mean is volume weighted: sum V q / sum V.");
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
    component = 0;
    if (variable.size() > 2 && variable[variable.size() - 2] == ' ')
      component = variable.back() - 'x';
  }

  double
  RegionCompute::evaluate(const std::function<double(unsigned int)> &value,
                          const std::vector<double>                 &volume,
                          const MPI_Comm                             comm,
                          const std::function<double(unsigned int)> &node_value,
                          const std::function<double(unsigned int)> &node_volume) const
  {
    const bool with_nodes = node_value && !nodes.empty();
    if (operation == "Minimum" || operation == "Maximum")
      {
        const double sign = operation == "Minimum" ? 1 : -1;
        double       best = std::numeric_limits<double>::max();
        for (const unsigned int i : points)
          best = std::min(best, sign * value(i));
        if (with_nodes)
          for (const unsigned int k : nodes)
            best = std::min(best, sign * node_value(k));
        return sign * Utilities::MPI::min(best, comm);
      }
    double sums[2] = {0, 0};
    for (const unsigned int i : points)
      {
        sums[0] += (operation == "Mean" ? volume[i] : 1.0) * value(i);
        sums[1] += volume[i];
      }
    if (with_nodes)
      for (const unsigned int k : nodes)
        {
          const double V = node_volume(k);
          sums[0] += (operation == "Mean" ? V : 1.0) * node_value(k);
          sums[1] += V;
        }
    Utilities::MPI::sum(ArrayView<const double>(sums, 2), comm, ArrayView<double>(sums, 2));
    return operation == "Mean" ? (sums[1] > 0 ? sums[0] / sums[1] : 0) : sums[0];
  }
} // namespace perideal
