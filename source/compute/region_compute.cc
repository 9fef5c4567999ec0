#include <perideal/compute/region_compute.h>
#include <perideal/output/checkpoint.h>

#include <perideal/continuum/continuum_field.h>

#include <perideal/base/registry.h>

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
    prm.declare_entry("Rate", "false", Patterns::Bool(),
                      "Also write the column NAME_rate: how fast the compute's value changes, per unit time "
                      "(with Variable = Crack tip and Operation = Maximum: the crack speed). It is 0 at the "
                      "first globals row.");
    prm.declare_entry("Rate window", "0", Patterns::Double(0),
                      "0: the rate between this globals row and the one before. A time T > 0: the "
                      "least-squares slope of the value over the globals rows of the last T, this one "
                      "included, which smooths a value that moves in steps (a crack tip advances from point "
                      "to point).");
    for (const auto &[name, entry] : Registry<PointQuantity>::instance().all())
      entry.declare(prm);
    for (const auto &[name, entry] : Registry<Reduction>::instance().all())
      entry.declare(prm);
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
    rate        = prm.get_bool("Rate");
    rate_window = prm.get_double("Rate window");
    AssertThrow(rate || rate_window == 0,
                ExcMessage(path + "/Rate window is " + prm.get("Rate window") +
                           ", but Rate is false: the window would smooth no column. Set Rate = true, or "
                           "remove the window"));
    history.clear();
    quantity  = Registry<PointQuantity>::instance().create(variable, path + "/Variable");
    quantity->parse_parameters(prm, path);
    reduction = Registry<Reduction>::instance().create(operation, path + "/Operation");
    reduction->parse_parameters(prm, path);
  }

  double
  RegionCompute::rate_of(const double value, const double time)
  {
    // The globals of one time taken again (the initial row, a summary's)
    // replace the earlier.
    if (!history.empty() && history.back().first == time)
      history.pop_back();
    // Rows older than the window go, but the row before this one always
    // stays: a window shorter than the rows' spacing is the two-row slope.
    while (history.size() > 1 && history.front().first < time - rate_window * (1 + 1e-9))
      history.pop_front();
    history.emplace_back(time, value);
    const std::size_t n = history.size();
    if (n < 2)
      return 0;
    double mean_t = 0, mean_q = 0;
    for (const auto &[t, q] : history)
      {
        mean_t += t / n;
        mean_q += q / n;
      }
    double stt = 0, stq = 0;
    for (const auto &[t, q] : history)
      {
        stt += (t - mean_t) * (t - mean_t);
        stq += (t - mean_t) * (q - mean_q);
      }
    return stt > 0 ? stq / stt : 0;
  }

  double
  RegionCompute::evaluate(const ComputeData &data, const double time, const MPI_Comm comm) const
  {
    std::vector<double>   q, V;
    std::vector<Point<3>> x;
    const bool            positions = reduction->needs_positions();
    q.reserve(points.size() + nodes.size());
    V.reserve(points.size() + nodes.size());
    for (const unsigned int i : points)
      {
        const double value = quantity->value(data, i);
        q.push_back(reference ? std::abs(value - reference->value(data.cloud.position(i), time)) : value);
        V.push_back(data.cloud.volume[i]);
        if (positions)
          x.push_back(data.cloud.position(i));
      }
    for (const unsigned int k : nodes)
      {
        // The lumped volume, for Mean: the node's lumped mass over its block's density.
        const auto  &node  = data.continuum->nodes[k];
        const double value = quantity->node_value(data, k);
        q.push_back(reference ? std::abs(value - reference->value(node.x, time)) : value);
        V.push_back(data.continuum->mass.local_element(node.local) / (*data.node_density)[k]);
        if (positions)
          x.push_back(node.x);
      }
    return reduction->reduce(q, V, x, comm);
  }

  void
  RegionCompute::save(CheckpointWriter &out) const
  {
    out.put(history);
  }

  void
  RegionCompute::load(CheckpointReader &in)
  {
    in.get(history);
  }
} // namespace perideal
