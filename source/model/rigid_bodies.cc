// Rigid blocks (rigid_bodies.h).

#include <perideal/base/format.h>
#include <perideal/conditions/condition_set.h>
#include <perideal/model/rigid_bodies.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/symmetric_tensor.h>

#include <cmath>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    using Vec = std::array<double, 3>;

    Vec
    cross(const Vec &a, const Vec &b)
    {
      return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
    }

    /// x with I x = b on the range of the symmetric I (the pseudo-inverse):
    /// a body whose points lie on a line has no inertia about it, and the
    /// angular velocity along that line is left 0.
    Vec
    solve_inertia(const double (&I)[3][3], const Vec &b)
    {
      // Scaled to entries of order 1 by a power of two (exact: the result is
      // the same to the bit): the eigenvalue solver squares the entries, and
      // the inertia of a dense body (1e300 kg m^2) would overflow there.
      double largest = 0;
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = 0; j < 3; ++j)
          largest = std::max(largest, std::abs(I[i][j]));
      Vec x = {{0, 0, 0}};
      if (!(largest > 0))
        return x;
      int exponent = 0;
      std::frexp(largest, &exponent);
      const double scale = std::ldexp(1.0, exponent);
      SymmetricTensor<2, 3> S;
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = i; j < 3; ++j)
          S[i][j] = I[i][j] / scale;
      const auto   eig   = eigenvectors(S); // largest eigenvalue first
      const double floor = 1e-12 * std::abs(eig[0].first);
      for (const auto &[lambda, e] : eig)
        if (lambda > floor && lambda > 0)
          {
            const double coefficient = (e[0] * b[0] + e[1] * b[1] + e[2] * b[2]) / lambda / scale;
            for (unsigned int d = 0; d < 3; ++d)
              x[d] += coefficient * e[d];
          }
      return x;
    }
  } // namespace

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
    // Mass, point count and the reference centre's first moment.
    std::vector<double> local(5 * bodies.size());
    for (unsigned int k = 0; k < bodies.size(); ++k)
      {
        for (const unsigned int i : bodies[k].points)
          {
            const double m = density[i] * cloud->volume[i];
            local[5 * k] += m;
            for (unsigned int d = 0; d < dim; ++d)
              local[5 * k + 2 + d] += m * cloud->X[dim * i + d];
          }
        local[5 * k + 1] = bodies[k].points.size();
      }
    Utilities::MPI::sum(local, comm, local);
    reference_centre.assign(bodies.size(), {{0, 0, 0}});
    for (unsigned int k = 0; k < bodies.size(); ++k)
      {
        bodies[k].mass     = local[5 * k];
        bodies[k].n_points = static_cast<unsigned int>(local[5 * k + 1]);
        AssertThrow(bodies[k].n_points > 0,
                    ExcMessage("Blocks/" + bodies[k].name + ": the rigid block holds no point (its Region or "
                               "Material ids select no cell)"));
        AssertThrow(bodies[k].mass > 0,
                    ExcMessage("Blocks/" + bodies[k].name + ": the rigid block has no mass: give its material a "
                               "positive Density"));
        for (unsigned int d = 0; d < dim; ++d)
          reference_centre[k][d] = local[5 * k + 2 + d] / bodies[k].mass;
      }
    check_inertia_finite();
  }

  void
  RigidBodies::check_inertia_finite() const
  {
    // The motion is solved from the mass and second moments about the origin
    // (sums()): a density whose moments leave the range of a double would stop
    // the run deep inside an eigenvalue solver instead of here.
    std::vector<double> inertia(bodies.size(), 0.0);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      for (const unsigned int i : bodies[k].points)
        for (unsigned int d = 0; d < dim; ++d)
          {
            const double y = cloud->X[dim * i + d];
            inertia[k] += (*mass_density)[i] * cloud->volume[i] * y * y;
          }
    Utilities::MPI::sum(inertia, comm, inertia);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      AssertThrow(std::isfinite(bodies[k].mass) && std::isfinite(inertia[k]),
                  ExcMessage("Blocks/" + bodies[k].name + ": the rigid block's mass (" + sci(bodies[k].mass, 3) +
                             ") or moment of inertia (" + sci(inertia[k], 3) +
                             ") leaves the range of a double: its material's Density is too large (or the "
                             "block too far from the origin) for the rigid-body motion"));
  }

  std::vector<RigidBodies::Sums>
  RigidBodies::sums(const double *u, const double *v, const double *f) const
  {
    constexpr unsigned int width = 21; // the doubles of one Sums
    std::vector<double>    local(width * bodies.size(), 0.0);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      {
        double *s = &local[width * k];
        for (const unsigned int i : bodies[k].points)
          {
            const double m = (*mass_density)[i] * cloud->volume[i];
            const Vec    y = {{cloud->X[dim * i] + u[dim * i], cloud->X[dim * i + 1] + u[dim * i + 1],
                               cloud->X[dim * i + 2] + u[dim * i + 2]}};
            const Vec    p = {{m * v[dim * i], m * v[dim * i + 1], m * v[dim * i + 2]}};
            const Vec    L = cross(y, p);
            for (unsigned int d = 0; d < dim; ++d)
              {
                s[d] += m * y[d];
                s[3 + d] += m * y[d] * y[d];
                s[9 + d] += p[d];
                s[12 + d] += L[d];
              }
            s[6] += m * y[0] * y[1];
            s[7] += m * y[1] * y[2];
            s[8] += m * y[0] * y[2];
            if (f)
              {
                const double V  = cloud->volume[i];
                const Vec    fi = {{f[dim * i] * V, f[dim * i + 1] * V, f[dim * i + 2] * V}};
                const Vec    T  = cross(y, fi);
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    s[15 + d] += fi[d];
                    s[18 + d] += T[d];
                  }
              }
          }
      }
    Utilities::MPI::sum(local, comm, local);
    std::vector<Sums> out(bodies.size());
    for (unsigned int k = 0; k < bodies.size(); ++k)
      {
        const double *s = &local[width * k];
        for (unsigned int d = 0; d < dim; ++d)
          {
            out[k].first[d]    = s[d];
            out[k].momentum[d] = s[9 + d];
            out[k].angular[d]  = s[12 + d];
            out[k].force[d]    = s[15 + d];
            out[k].torque[d]   = s[18 + d];
          }
        for (unsigned int c = 0; c < 6; ++c)
          out[k].second[c] = s[3 + c];
      }
    return out;
  }

  RigidBodies::Motion
  RigidBodies::motion(const Body &body, const Sums &s) const
  {
    Motion       m;
    const double M = body.mass;
    for (unsigned int d = 0; d < dim; ++d)
      {
        m.centre[d]   = s.first[d] / M;
        m.velocity[d] = s.momentum[d] / M;
      }
    // Second moment about the centre, J = sum m y y^T - M c c^T; I = tr(J) 1 - J.
    static constexpr unsigned int index[3][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}};
    double                        J[3][3];
    for (unsigned int a = 0; a < 3; ++a)
      for (unsigned int b = 0; b < 3; ++b)
        J[a][b] = s.second[index[a][b]] - M * m.centre[a] * m.centre[b];
    const double trace = J[0][0] + J[1][1] + J[2][2];
    for (unsigned int a = 0; a < 3; ++a)
      for (unsigned int b = 0; b < 3; ++b)
        m.inertia[a][b] = (a == b ? trace : 0.0) - J[a][b];
    if (body.translates_only)
      m.omega = {{0, 0, 0}};
    else
      {
        // Angular momentum about the centre: about the origin minus c x P.
        const Vec cP = cross(m.centre, s.momentum);
        m.omega      = solve_inertia(m.inertia, {{s.angular[0] - cP[0], s.angular[1] - cP[1], s.angular[2] - cP[2]}});
      }
    return m;
  }

  void
  RigidBodies::apply(double *f, const double *u, const double *v)
  {
    if (bodies.empty())
      return;
    const std::vector<Sums> s = sums(u, v, f);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      {
        Body        &body = bodies[k];
        const Motion m    = motion(body, s[k]);
        const Vec    cF   = cross(m.centre, s[k].force);
        for (unsigned int d = 0; d < dim; ++d)
          {
            body.force[d]  = s[k].force[d];
            body.torque[d] = s[k].torque[d] - cF[d];
          }
        Vec alpha = {{0, 0, 0}};
        if (!body.translates_only)
          {
            // Euler's equations: I alpha = T - omega x I omega.
            Vec Iw = {{0, 0, 0}};
            for (unsigned int a = 0; a < 3; ++a)
              for (unsigned int b = 0; b < 3; ++b)
                Iw[a] += m.inertia[a][b] * m.omega[b];
            const Vec gyro = cross(m.omega, Iw);
            alpha          = solve_inertia(m.inertia, {{body.torque[0] - gyro[0], body.torque[1] - gyro[1],
                                                       body.torque[2] - gyro[2]}});
          }
        for (const unsigned int i : body.points)
          {
            const Vec r   = {{cloud->X[dim * i] + u[dim * i] - m.centre[0],
                              cloud->X[dim * i + 1] + u[dim * i + 1] - m.centre[1],
                              cloud->X[dim * i + 2] + u[dim * i + 2] - m.centre[2]}};
            const Vec ar  = cross(alpha, r);
            const Vec wwr = cross(m.omega, cross(m.omega, r));
            for (unsigned int d = 0; d < dim; ++d)
              f[dim * i + d] = (*mass_density)[i] * (body.force[d] / body.mass + ar[d] + wwr[d]);
          }
      }
  }

  void
  RigidBodies::unify_velocities(const double *u, double *v) const
  {
    if (bodies.empty())
      return;
    const std::vector<Sums> s = sums(u, v, nullptr);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      {
        const Motion m = motion(bodies[k], s[k]);
        for (const unsigned int i : bodies[k].points)
          {
            const Vec r  = {{cloud->X[dim * i] + u[dim * i] - m.centre[0],
                             cloud->X[dim * i + 1] + u[dim * i + 1] - m.centre[1],
                             cloud->X[dim * i + 2] + u[dim * i + 2] - m.centre[2]}};
            const Vec wr = cross(m.omega, r);
            for (unsigned int d = 0; d < dim; ++d)
              v[dim * i + d] = m.velocity[d] + wr[d];
          }
      }
  }

  void
  RigidBodies::check_constraints(const ConditionSet &conditions)
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
            // A guided body (a crosshead): it translates along its free components.
            if (n > 0)
              bodies[k].translates_only = true;
          }
  }

  void
  RigidBodies::add_globals(std::vector<std::pair<std::string, double>> &row, const double *u, const double *v) const
  {
    if (bodies.empty())
      return;
    const std::vector<Sums> s = sums(u, v, nullptr);
    for (unsigned int k = 0; k < bodies.size(); ++k)
      {
        const Body  &body = bodies[k];
        const Motion m    = motion(body, s[k]);
        for (unsigned int d = 0; d < dim; ++d)
          row.emplace_back(body.name + "_velocity_" + "xyz"[d], m.velocity[d]);
        for (unsigned int d = 0; d < dim; ++d)
          row.emplace_back(body.name + "_displacement_" + "xyz"[d], m.centre[d] - reference_centre[k][d]);
        for (unsigned int d = 0; d < dim; ++d)
          row.emplace_back(body.name + "_angular_velocity_" + "xyz"[d], m.omega[d]);
        for (unsigned int d = 0; d < dim; ++d)
          row.emplace_back(body.name + "_force_" + "xyz"[d], body.force[d]);
      }
  }
} // namespace perideal
