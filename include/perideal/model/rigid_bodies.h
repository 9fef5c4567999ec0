#pragma once
// Rigid blocks (Blocks/NAME/Type = Rigid): an impactor or an indenter that
// needs no bonds of its own. Each rigid block is one body of mass
// M = sum m_i (m_i = rho_i V_i, its material's density) and inertia tensor
// I = sum m_i (|r_i|^2 1 - r_i r_i^T) about its centre of mass c (r_i =
// y_i - c), moved by the sum F of its points' forces and their torque T
// about c (contact and loads). Every point's force density becomes rho_i a_i
// with a_i = F/M + alpha x r_i + omega x (omega x r_i), the acceleration of
// that point of a rigid body with angular velocity omega (from the points'
// angular momentum, omega = I^-1 L) and angular acceleration alpha =
// I^-1 (T - omega x I omega) (Euler's equations in the current frame). So
// sum m_i a_i = F and sum m_i r_i x a_i = T exactly: the integrator moves
// the points without knowing about bodies, and linear and angular momentum
// are kept as for any pair forces. The points stay a rigid body to second
// order in omega dt per step (the drift follows the tangent of the
// rotation), which over an impact is far below the point spacing.
// A prescribed velocity or displacement on all of a body's points in a
// component moves it along that component (a testing machine's crosshead);
// such a body translates only, and F is the reaction it meets.

#include <perideal/discretization/point_cloud.h>
#include <perideal/model/block.h>

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace perideal
{
  class ConditionSet;

  class RigidBodies
  {
  public:
    struct Body
    {
      unsigned int              block = 0;
      std::string               name;
      double                    mass = 0;       // over all ranks
      unsigned int              n_points = 0;   // over all ranks
      bool                      translates_only = false; // a prescribed component, or no extent to turn
      std::vector<unsigned int> points;         // owned
      std::array<double, 3>     force{{0, 0, 0}};  // sum of the points' forces at the last evaluation (all ranks)
      std::array<double, 3>     torque{{0, 0, 0}}; // their torque about the centre of mass, same evaluation
    };

    /// The rigid blocks of @p blocks and their masses. Collective.
    void
    setup(const std::vector<Block> &blocks, const PointCloud &cloud, const std::vector<double> &mass_density,
          MPI_Comm comm);

    bool
    empty() const
    {
      return bodies.empty();
    }

    /// Sums each body's force and torque (force density times volume over
    /// its points at the current positions X + @p u, all ranks) and replaces
    /// every point's force density by rho_i a_i (above), omega taken from
    /// the velocities @p v. One collective if there are bodies.
    void
    apply(double *force_density, const double *u, const double *v);

    /// Gives every point of a body the velocity of a rigid motion with the
    /// body's momentum and angular momentum (initial conditions set point
    /// by point). Collective if there are bodies.
    void
    unify_velocities(const double *u, double *velocity) const;

    /// Stops with an Error naming the condition if a prescribed condition
    /// holds some but not all points of a body in a component; a body with
    /// a prescribed component translates only. Collective.
    void
    check_constraints(const ConditionSet &conditions);

    /// The globals columns of every body: the velocity and displacement of
    /// its centre of mass, its angular velocity, and the force F. Collective
    /// if there are bodies.
    void
    add_globals(std::vector<std::pair<std::string, double>> &row, const double *displacement,
                const double *velocity) const;

    std::vector<Body> bodies;

  private:
    /// Per body, summed over ranks: M c, the second moment sum m y y^T, the
    /// momentum, the angular momentum about the origin, and (with @p f) the
    /// force and its torque about the origin.
    struct Sums
    {
      std::array<double, 3> first, momentum, angular, force, torque;
      std::array<double, 6> second; // xx yy zz xy yz xz
    };
    /// The kinematics of a body from its Sums: centre, inertia about it,
    /// velocity of the centre, angular velocity.
    struct Motion
    {
      std::array<double, 3> centre, velocity, omega;
      double                inertia[3][3];
    };
    std::vector<Sums>
    sums(const double *u, const double *v, const double *f) const;
    Motion
    motion(const Body &body, const Sums &s) const;
    /// Collective: stops, naming the block, if its mass or second moment is
    /// not finite.
    void
    check_inertia_finite() const;

    std::vector<std::array<double, 3>> reference_centre; // per body: its centre of mass at X
    const PointCloud          *cloud        = nullptr;
    const std::vector<double> *mass_density = nullptr;
    MPI_Comm                   comm         = MPI_COMM_NULL;
  };
} // namespace perideal
