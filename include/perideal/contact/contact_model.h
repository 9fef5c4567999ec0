#pragma once
// The ContactModel interface: a short-range force between points that are
// not bonded to each other, points of different bodies or the two sides of
// broken bonds, once they come closer than a contact radius. Without it,
// bodies and fragments pass through each other.
//
// The core (not the model) finds the candidate pairs: the points whose
// current positions are within contact_radius() (plus a skin, so that the
// search need not run every step), excluding pairs bonded and intact. The
// model evaluates its force over that list, pair by pair, adding equal and
// opposite forces to both points (action equals reaction). Friction needs the
// relative velocity of a pair and a coefficient (Coulomb: |f_t| <= mu |f_n|),
// so the model sees the velocities and parses its own friction keys.
//
// A model is one file in source/contact/ with PERIDEAL_REGISTER(ContactModel,
// ClassName, "Name", "documentation") at its bottom. No model is registered
// and no key of the parameter file chooses one yet.

#include <perideal/base/input.h>
#include <perideal/base/registry.h>
#include <perideal/discretization/point_cloud.h>

#include <deal.II/lac/la_parallel_vector.h>

#include <string>
#include <utility>
#include <vector>

namespace perideal
{
  /// Two points, local indices (owned or ghost), in contact range.
  using ContactPair = std::pair<unsigned int, unsigned int>;

  /// The state a contact force depends on; vectors hold dim entries per
  /// point, ghost values current.
  struct ContactState
  {
    const PointCloud                                        &cloud; // reference positions, volumes
    const dealii::LinearAlgebra::distributed::Vector<double> &displacement;
    const dealii::LinearAlgebra::distributed::Vector<double> &velocity;
    const std::vector<double>                                &mass_density; // per point
  };

  class ContactModel
  {
  public:
    virtual ~ContactModel() = default;

    /// Reads the model's keys (declared by its static declare_parameters)
    /// from the current subsection; @p path names it in errors.
    virtual void
    parse_parameters(ParameterHandler &prm, const std::string &path) = 0;

    /// The distance below which two points interact: the reach of the
    /// proximity search.
    virtual double
    contact_radius() const = 0;

    /// Adds the contact force density of every pair of @p pairs to @p force
    /// (dim per point) at both of its points. Serial: no MPI.
    virtual void
    compute_force(const ContactState                               &state,
                  const std::vector<ContactPair>                   &pairs,
                  dealii::LinearAlgebra::distributed::Vector<double> &force) const = 0;

    /// The largest stable explicit step the contact stiffness allows (the
    /// integrator takes the minimum with the materials').
    virtual double
    stable_time_step(const ContactState &state) const = 0;
  };
} // namespace perideal
