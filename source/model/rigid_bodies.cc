// Rigid blocks (rigid_bodies.h).

#include <perideal/base/format.h>
#include <perideal/conditions/condition_set.h>
#include <perideal/model/rigid_bodies.h>
#include <perideal/model/state.h>

#include <deal.II/base/mpi.h>

namespace perideal
{
  using namespace dealii;

  void
  RigidBodies::setup(const std::vector<Block> &blocks, const PointCloud &cloud_, const std::vector<double> &density,
                     MPI_Comm comm_)
  {
    cloud        = &cloud_;
    mass_density = &density;
    comm         = comm_;
    bodies.clear();
    for (unsigned int b = 0; b < blocks.size(); ++b)
      if (blocks[b].rigid)
        {
          Body body;
          body.block = b;
          body.name  = blocks[b].name;
          for (unsigned int i = 0; i < cloud->n_owned(); ++i)
            if (cloud->block[i] == b)
              body.points.push_back(i);
          bodies.push_back(std::move(body));
        }
    if (bodies.empty())
      return;
    std::vector<double> local(2 * bodies.size());
    for (unsigned int k = 0; k < bodies.size(); ++k)
      {
        for (const unsigned int i : bodies[k].points)
          local[2 * k] += density[i] * cloud->volume[i];
        local[2 * k + 1] = bodies[k].points.size();
      }
    Utilities::MPI::sum(local, comm, local);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      {
        bodies[k].mass     = local[2 * k];
        bodies[k].n_points = static_cast<unsigned int>(local[2 * k + 1]);
        AssertThrow(bodies[k].n_points > 0,
                    ExcMessage("Blocks/" + bodies[k].name + ": the rigid block holds no point (its Region or "
                               "Material ids select no cell)"));
        AssertThrow(bodies[k].mass > 0,
                    ExcMessage("Blocks/" + bodies[k].name + ": the rigid block has no mass: give its material a "
                               "positive Density"));
      }
    sums.resize(dim * bodies.size());
  }

  void
  RigidBodies::apply(double *f)
  {
    if (bodies.empty())
      return;
    std::fill(sums.begin(), sums.end(), 0.0);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      for (const unsigned int i : bodies[k].points)
        for (unsigned int d = 0; d < dim; ++d)
          sums[dim * k + d] += f[dim * i + d] * cloud->volume[i];
    Utilities::MPI::sum(sums, comm, sums);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      {
        Body &body = bodies[k];
        for (unsigned int d = 0; d < dim; ++d)
          body.force[d] = sums[dim * k + d];
        for (const unsigned int i : body.points)
          for (unsigned int d = 0; d < dim; ++d)
            f[dim * i + d] = (*mass_density)[i] * body.force[d] / body.mass;
      }
  }

  void
  RigidBodies::unify_velocities(double *v) const
  {
    if (bodies.empty())
      return;
    std::vector<double> momentum(dim * bodies.size(), 0.0);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      for (const unsigned int i : bodies[k].points)
        for (unsigned int d = 0; d < dim; ++d)
          momentum[dim * k + d] += (*mass_density)[i] * cloud->volume[i] * v[dim * i + d];
    Utilities::MPI::sum(momentum, comm, momentum);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      for (const unsigned int i : bodies[k].points)
        for (unsigned int d = 0; d < dim; ++d)
          v[dim * i + d] = momentum[dim * k + d] / bodies[k].mass;
  }

  void
  RigidBodies::check_constraints(const ConditionSet &conditions) const
  {
    if (bodies.empty())
      return;
    // Per body, component and condition: how many of the body's points the
    // condition prescribes.
    std::vector<int> body_of(cloud->n_owned(), -1);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      for (const unsigned int i : bodies[k].points)
        body_of[i] = k;
    const unsigned int  n_conditions = conditions.conditions.size();
    std::vector<double> held(bodies.size() * dim * n_conditions, 0.0);
    for (const auto &c : conditions.constraints)
      if (c.dof < dim * cloud->n_owned() && body_of[c.dof / dim] >= 0)
        held[(body_of[c.dof / dim] * dim + c.dof % dim) * n_conditions + c.condition] += 1;
    Utilities::MPI::sum(held, comm, held);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      for (unsigned int d = 0; d < dim; ++d)
        for (unsigned int c = 0; c < n_conditions; ++c)
          {
            const double n = held[(k * dim + d) * n_conditions + c];
            AssertThrow(n == 0 || n == bodies[k].n_points,
                        ExcMessage("Boundary conditions/" + conditions.conditions[c].name + " prescribes the " +
                                   std::string(1, "xyz"[d]) + " motion of " + std::to_string(int(n)) + " of the " +
                                   std::to_string(bodies[k].n_points) + " points of rigid block '" + bodies[k].name +
                                   "': a rigid block moves as one; give the condition a region that holds "
                                   "the whole block, or none of it"));
          }
  }

  void
  RigidBodies::add_globals(std::vector<std::pair<std::string, double>> &row, const double *u, const double *v) const
  {
    if (bodies.empty())
      return;
    std::vector<double> sums_uv(2 * dim * bodies.size(), 0.0);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      for (const unsigned int i : bodies[k].points)
        {
          const double m = (*mass_density)[i] * cloud->volume[i];
          for (unsigned int d = 0; d < dim; ++d)
            {
              sums_uv[2 * dim * k + d] += m * v[dim * i + d];
              sums_uv[2 * dim * k + dim + d] += m * u[dim * i + d];
            }
        }
    Utilities::MPI::sum(sums_uv, comm, sums_uv);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      {
        const Body &body = bodies[k];
        for (unsigned int d = 0; d < dim; ++d)
          row.emplace_back(body.name + "_velocity_" + "xyz"[d], sums_uv[2 * dim * k + d] / body.mass);
        for (unsigned int d = 0; d < dim; ++d)
          row.emplace_back(body.name + "_displacement_" + "xyz"[d], sums_uv[2 * dim * k + dim + d] / body.mass);
        for (unsigned int d = 0; d < dim; ++d)
          row.emplace_back(body.name + "_force_" + "xyz"[d], body.force[d]);
      }
  }
} // namespace perideal
