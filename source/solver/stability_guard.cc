// Where a run that blows up went wrong (stability_guard.h).

#include <perideal/base/format.h>
#include <perideal/continuum/coupling.h>
#include <perideal/solver/stability_guard.h>

#include <cmath>

namespace perideal
{
  using namespace dealii;

  BestPoint
  StabilityGuard::fastest_point() const
  {
    const PointCloud      &cloud     = access.discretization.cloud;
    const MechanicalState &state     = access.state;
    const ContinuumField  *continuum = access.coupling ? &access.coupling->continuum : nullptr;
    const MPI_Comm         comm      = access.comm;
    BestPoint fastest(BestPoint::Order::largest);
    const double *v = state.velocity.begin();
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (!access.discretization.is_virtual(i)) // a virtual point follows the FE nodes, looked at below
        fastest.consider(std::hypot(v[3 * i], v[3 * i + 1], v[3 * i + 2]), cloud.gid[i], &cloud.X[3 * i]);
    if (continuum) // FE nodes: one velocity component per DoF
      for (const auto &node : continuum->nodes)
        fastest.consider(std::abs(continuum->V.local_element(node.local)),
                         continuum->V.get_partitioner()->local_to_global(node.local), &node.x[0],
                         BestPoint::Kind::fe_dof);
    return fastest.global(comm);
  }

  std::string
  StabilityGuard::locate_nonfinite() const
  {
    const PointCloud      &cloud     = access.discretization.cloud;
    const MechanicalState &state     = access.state;
    const ContinuumField  *continuum = access.coupling ? &access.coupling->continuum : nullptr;
    const MPI_Comm         comm      = access.comm;
    // The first point (smallest global id; then FE DoFs) with a non-finite
    // displacement, velocity or force: the same on any number of ranks.
    BestPoint     first(BestPoint::Order::smallest);
    const auto    finite = [](const VectorType &w, const unsigned int k) { return std::isfinite(w.local_element(k)); };
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      for (unsigned int d = 0; d < dim; ++d)
        if (!finite(state.velocity, dim * i + d) || !finite(state.displacement, dim * i + d) || !finite(state.force, dim * i + d))
          {
            first.consider(0, cloud.gid[i], &cloud.X[3 * i]);
            break;
          }
    if (continuum)
      for (const auto &node : continuum->nodes)
        if (!finite(continuum->U, node.local) || !finite(continuum->V, node.local) ||
            !finite(continuum->F, node.local))
          first.consider(0, continuum->U.get_partitioner()->local_to_global(node.local), &node.x[0],
                         BestPoint::Kind::fe_dof);
    const BestPoint where = first.global(comm);
    if (where.found)
      return where.describe();
    // Finite values whose kinetic energy overflows.
    const BestPoint fastest = fastest_point();
    return "the kinetic energy overflows (no value is non-finite yet): the fastest " + fastest.describe() +
           ", speed " + sci(fastest.value);
  }
} // namespace perideal
