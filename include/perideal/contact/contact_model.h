#pragma once
// The ContactModel interface: a short-range force between points that are
// not bonded to each other (points of different bodies, or the two sides of
// broken bonds) once they come closer than a contact radius. Without it,
// bodies and fragments pass through each other.
//
// The core (contact/contact.h), not the model, finds the candidate pairs in
// the current configuration, across ranks, and keeps them in a Verlet list.
// A model evaluates its force over the list of pairs the core gives it, one
// virtual call per list: for every pair (i, j), i one of this rank's points,
// it adds the force on i (as force density, divided by V_i) and half the
// pair's energy and friction power. The rank that owns j evaluates the same
// pair from j's side with the same arithmetic, so the two forces are equal and
// opposite bit for bit (d_ji = -d_ij exactly; every product is commutative).
//
// A model is one file in source/contact/ with PERIDEAL_REGISTER(ContactModel,
// ClassName, "Name", "documentation") at its bottom; Contact models/<name>/
// Model chooses it by that name.

#include <perideal/base/input.h>
#include <perideal/base/registry.h>

#include <cstddef>
#include <string>

namespace perideal
{
  /// The points the contact sees, in its own local numbering: this rank's
  /// owned points first (the point cloud's owned numbering), then the
  /// contact ghosts (points of other ranks near this rank's deformed region).
  struct ContactPoints
  {
    const double *X;       // reference position, dim per point
    const double *uv;      // displacement, then velocity if a model uses_velocity(): stride per point
    unsigned int  stride;  // dim, or 2 dim with velocity
    const double *volume;  // V
    const double *mass;    // rho V (0 at points without mass)
    const double *horizon; // the horizon of the point's block
    double        time = 0, dt = 0;
    // Only for models that ask for it (uses_contact_counts()): per point the
    // pairs within their contact radius now, over all models, ghosts included.
    const double *contacts = nullptr;
  };

  /// What a model adds for the owned points of its pairs.
  struct ContactOutput
  {
    double *force;                 // force density, dim per owned point (added to)
    double  energy            = 0; // sum of half the pair energies (potential of the contact springs)
    double  friction_power    = 0; // sum of half the pairs' f_t . (v_i - v_j): <= 0, what friction dissipates
  };

  class ContactModel
  {
  public:
    virtual ~ContactModel() = default;

    /// Reads the model's keys (declared by its static declare_parameters)
    /// from the current subsection; @p path names it in errors.
    virtual void
    parse_parameters(ParameterHandler &prm, const std::string &path) = 0;

    /// The distance below which two points interact.
    virtual double
    contact_radius() const = 0;

    /// Whether compute_force() reads ContactPoints::contacts (the core then
    /// counts and exchanges them before the evaluation).
    virtual bool
    uses_contact_counts() const
    {
      return false;
    }

    /// Whether compute_force() reads the velocities (ContactPoints::uv
    /// beyond the displacement); without, only displacements travel between
    /// ranks.
    virtual bool
    uses_velocity() const
    {
      return false;
    }

    /// The normal stiffness of a pair per V_i V_j at time @p time (the pair
    /// spring is k V_i V_j, N/m) for points of horizon @p horizon: what the
    /// stable time step needs.
    virtual double
    stiffness(const double horizon, const double time) const = 0;

    /// Adds the force of every pair (first[p], second[p]), p < n, on its
    /// first point (owned) to @p out. Serial: no MPI.
    virtual void
    compute_force(const ContactPoints &points, const unsigned int *first, const unsigned int *second,
                  const std::size_t n, ContactOutput &out) const = 0;
  };

  /// Declares the Model key of a Contact models subsection.
  void
  declare_contact_model_entry(ParameterHandler &prm);
} // namespace perideal
