#pragma once
// The state the time integrators advance and the record of a run.
//
// MechanicalState is one set of degrees of freedom over the whole body: the
// dim entries of every owned peridynamic point and the owned FE DoFs of
// continuum blocks, numbered 0 .. size()-1 in that order. Every DoF k has a
// displacement u, velocity v, force f, a measure w and a mass density rho:
// at a point, f is the force density, w the point's volume and rho its
// density (0 at virtual points, which follow the FE field); at an FE DoF, f
// is the nodal force, w = 1 and rho the lumped nodal mass. So w f is a force
// and rho w a mass everywhere, and the integrators, conditions and reports
// write each of kick, drift, predictor, residual, load work and reaction as
// one loop over DoFs (for_each()), not a point twin and an FE twin.
//
// The points' vectors are the force model's (ghosted on the point
// partitioner); the FE ones stay the continuum's (ghosted on its DoF
// partitioner), reached through the numbering.

#include <perideal/material/material.h>

#include <deal.II/base/point.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace perideal
{
  class ContinuumField;
  class Discretization;
  class CheckpointWriter;
  class CheckpointReader;

  class MechanicalState
  {
  public:
    VectorType          displacement; // the points' entries, ghosted, dim per point
    VectorType          velocity, force;
    std::vector<double> energy_density; // per owned point (written by evaluations with energy)
    std::vector<double> mass_density;   // per owned point; 0 at virtual points
    // Newmark only: a per DoF (size()); empty otherwise (supports then carry -w f).
    std::vector<double> acceleration;

    /// Numbers the DoFs of the discretization's owned points and of
    /// @p continuum (null without continuum blocks). Takes the inverse
    /// densities from mass_density: call after the force model's setup.
    void
    number_dofs(const Discretization &discretization, ContinuumField *continuum);

    /// All owned DoFs.
    unsigned int
    size() const
    {
      return n_point_entries + n_fe;
    }
    /// DoFs 0 .. point_entries()-1 are the points' (dim per owned point).
    unsigned int
    point_entries() const
    {
      return n_point_entries;
    }
    bool
    is_fe(const unsigned int k) const
    {
      return k >= n_point_entries;
    }
    /// The local index of FE DoF @p k in the continuum's vectors.
    unsigned int
    fe_local(const unsigned int k) const
    {
      return k - n_point_entries;
    }
    /// The point of point DoF @p k.
    unsigned int
    point(const unsigned int k) const
    {
      return k / dim;
    }
    bool
    has_fe() const
    {
      return continuum != nullptr;
    }

    double &
    u(const unsigned int k);
    double
    u(const unsigned int k) const;
    double &
    v(const unsigned int k);
    double
    v(const unsigned int k) const;
    double
    f(const unsigned int k) const;
    double
    measure(const unsigned int k) const;
    double
    density(const unsigned int k) const;
    /// The mass rho w of DoF @p k.
    double
    mass(const unsigned int k) const
    {
      return density(k) * measure(k);
    }
    /// The continuum's node (ContinuumField::nodes) of FE DoF @p k.
    unsigned int
    fe_node(const unsigned int k) const
    {
      return node_of[fe_local(k)];
    }
    /// An FE DoF constrained by hanging nodes: it follows its masters.
    bool
    is_hanging(const unsigned int k) const
    {
      return is_fe(k) && !fe_moves[fe_local(k)];
    }
    /// A virtual point's entries follow the FE field: no equation of their own.
    bool
    is_virtual(const unsigned int k) const;
    dealii::Point<dim>
    position(const unsigned int k) const;
    unsigned int
    component(const unsigned int k) const;
    /// A point's hash (random fields in conditions); 0 at FE DoFs.
    std::uint64_t
    hash(const unsigned int k) const;

    /// One DoF as for_each() hands it over.
    struct DoF
    {
      unsigned int number;
      double      &u, &v;
      double       f, density, inverse_density, measure;
    };

    /// Calls body(DoF) for every DoF that moves by an equation of motion or
    /// is prescribed: every point entry, virtual ones included (inverse
    /// density 0), and the FE DoFs free of hanging-node constraints (those
    /// follow their masters: distribute()). Plain loops over flat arrays.
    template <typename Body>
    void
    for_each(const Body &body);

    /// The FE DoFs constrained by hanging nodes take their masters'
    /// displacement, or velocity. No-ops without them. Collective.
    void
    distribute_displacement();
    void
    distribute_velocity();
    /// v = 0 at every DoF, hanging ones included.
    void
    set_velocity_zero();

    /// u, v, f and a of every owned DoF (checkpoint.h); load() leaves the
    /// ghosts to the caller (SimulatorAccess::update_ghosts()).
    void
    save(CheckpointWriter &out) const;
    void
    load(CheckpointReader &in);

  private:
    unsigned int              n_point_entries = 0, n_fe = 0;
    const Discretization     *discretization  = nullptr;
    const double             *point_measure   = nullptr; // the points' volumes
    ContinuumField           *continuum       = nullptr;
    double                   *U = nullptr, *V = nullptr;
    const double             *F = nullptr, *M = nullptr;
    std::vector<double>       point_inverse_density; // per owned point
    std::vector<double>       fe_inverse_mass;       // per owned FE DoF
    std::vector<unsigned int> node_of;               // FE local index -> the continuum's node
    std::vector<std::uint8_t> fe_moves;              // per owned FE DoF: 1 unless hanging
    const std::vector<unsigned int> *fe_free = nullptr;
    bool                      hanging = false;
  };

  template <typename Body>
  inline void
  MechanicalState::for_each(const Body &body)
  {
    double *const       pu = displacement.begin(), *const pv = velocity.begin();
    const double *const pf = force.begin();
    const double *const w  = point_measure;
    for (unsigned int k = 0; k < n_point_entries; ++k)
      body(DoF{k, pu[k], pv[k], pf[k], mass_density[k / dim], point_inverse_density[k / dim], w[k / dim]});
    for (const unsigned int l : *fe_free)
      body(DoF{n_point_entries + l, U[l], V[l], F[l], M[l], fe_inverse_mass[l], 1.0});
  }

  /// What the last implicit solve of a step took.
  struct NewtonResult
  {
    unsigned int newton_iterations = 0, linear_iterations = 0;
    double       residual          = 0;
    std::string  failure; // why the solve failed (the run's error without adaptive steps); empty: converged
  };

  /// Time step and energy bookkeeping of a run, and its warnings.
  struct RunRecord
  {
    /// What a continued run needs of it (checkpoint.h): all but the
    /// start-up figures.
    void
    save(CheckpointWriter &out) const;
    void
    load(CheckpointReader &in);

    double       dt = 0, dt_stable = 0;
    double       external_work = 0, initial_energy = 0, last_strain_energy = 0, last_kinetic_energy = 0;
    double       dissipated_energy = 0; // released by broken bonds (ForceModel::released_energy)
    // Adaptivity: the energy the conversions added (after - before, summed), in the balance.
    double       conversion_energy = 0;
    unsigned int conversions = 0;        // Adaptivity: conversions so far
    double       converted_cells = 0;    // cells converted so far (all ranks)
    double       conversion_seconds = 0; // spent in the checks and conversions
    // Dissipated by the materials (plastic, viscous work) up to the last
    // globals row: FieldStore::dissipated_energy(), summed over ranks.
    double       material_dissipation = 0;
    // Contact: the springs' energy at the last globals row, and the work of
    // friction so far (each step's friction power times dt, >= 0).
    double       last_contact_energy = 0, contact_dissipation = 0;
    unsigned int shortened_steps   = 0; // Verlet steps shortened below the elastic step
    double       shortest_dt       = std::numeric_limits<double>::max();
    double       startup_memory    = 0; // resident bytes before the scene is read
    double       setup_seconds     = 0;
    NewtonResult last_newton;           // implicit runs: the last step's solves
    unsigned int last_damage_solves = 0;
    // Implicit runs, Adaptive steps: the sub-steps cut so far, the smallest fraction of a step.
    unsigned int step_cuts = 0;
    double       smallest_step_fraction = 1;
    std::vector<std::string> warnings;
  };
} // namespace perideal
