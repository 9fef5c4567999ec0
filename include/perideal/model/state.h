#pragma once
// The state the time integrators advance and the record of a run: the
// peridynamic points' displacement, velocity and force density (ghosted on
// the point partitioner), their mass density and strain energy density, and
// the diagonstics (time step, energies, work) the report and the globals read.
// The FE nodes of continuum blocks keep theirs in the Coupling's
// ContinuumField.

#include <perideal/material/material.h>

#include <limits>
#include <string>
#include <vector>

namespace perideal
{
  struct MechanicalState
  {
    VectorType          displacement; // ghosted, dim per point
    VectorType          velocity, force;
    std::vector<double> energy_density; // per owned point (written by evaluations with energy)
    std::vector<double> mass_density;   // per owned point; 0 at virtual points
    // Newmark only: the acceleration of the owned DoFs (PD entries, and FE
    // DoFs of continuum blocks); empty otherwise (supports then carry -V f).
    std::vector<double> acceleration, fe_acceleration;
  };

  /// What the last implicit solve of a step took.
  struct NewtonResult
  {
    unsigned int newton_iterations = 0, linear_iterations = 0;
    double       residual          = 0;
  };

  /// Time step and energy bookkeeping of a run, and its warnings.
  struct RunRecord
  {
    double       dt = 0, dt_stable = 0;
    double       external_work = 0, initial_energy = 0, last_strain_energy = 0, last_kinetic_energy = 0;
    double       dissipated_energy = 0; // released by broken bonds (ForceModel::released_energy)
    unsigned int shortened_steps   = 0; // Verlet steps shortened below the elastic step
    double       shortest_dt       = std::numeric_limits<double>::max();
    double       startup_memory    = 0; // resident bytes before the scene is read
    double       setup_seconds     = 0;
    NewtonResult last_newton;           // implicit runs: the last step's solves
    unsigned int last_damage_solves = 0;
    std::vector<std::string> warnings;
  };
} // namespace perideal
