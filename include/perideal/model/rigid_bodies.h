#pragma once
// Rigid blocks (Blocks/NAME/Type = Rigid): an impactor or an indenter that
// needs no bonds of its own. Each rigid block is one body of mass
// M = sum rho_i V_i (its material's density) that translates under the sum F
// of its points' forces (contact and loads): every point's force density
// becomes rho_i F / M, so every point gets the acceleration F / M and the
// integrator moves the points together without knowing about bodies. The
// body does not rotate: the torque of off-centre contact forces is taken up
// (its angular momentum is not kept), which suits a projectile or indenter
// that hits squarely. A prescribed velocity or displacement on all of a
// body's points in a component moves it along that component (a testing
// machine's crosshead); F is then the reaction the body meets.

#include <perideal/discretization/point_cloud.h>
#include <perideal/model/block.h>

#include <array>
#include <string>
#include <utility>
#include <vector>

namespace perideal
{
  class ConditionSet;
  class MechanicalState;

  class RigidBodies
  {
  public:
    struct Body
    {
      unsigned int              block = 0;
      std::string               name;
      double                    mass = 0;       // over all ranks
      unsigned int              n_points = 0;   // over all ranks
      std::vector<unsigned int> points;         // owned
      std::array<double, 3>     force{{0, 0, 0}}; // sum of the points' forces at the last evaluation (all ranks)
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

    /// Sums each body's force (force density times volume over its points,
    /// all ranks) and replaces every point's force density by rho_i F / M.
    /// Collective if there are bodies.
    void
    apply(double *force_density);

    /// Gives every point of a body the body's velocity: its momentum over
    /// its mass (initial conditions set point by point). Collective if there
    /// are bodies.
    void
    unify_velocities(double *velocity) const;

    /// Stops with an Error naming the condition if a prescribed condition
    /// holds some but not all points of a body in a component. Collective.
    void
    check_constraints(const ConditionSet &conditions) const;

    /// The globals columns of every body: the velocity and displacement of
    /// its centre of mass and the force F. Collective if there are bodies.
    void
    add_globals(std::vector<std::pair<std::string, double>> &row, const double *displacement,
                const double *velocity) const;

    std::vector<Body> bodies;

  private:
    const PointCloud          *cloud        = nullptr;
    const std::vector<double> *mass_density = nullptr;
    MPI_Comm                   comm         = MPI_COMM_NULL;
    std::vector<double>        sums; // apply(): one sum over ranks for all bodies
  };
} // namespace perideal
