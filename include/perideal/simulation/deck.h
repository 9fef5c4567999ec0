#pragma once
// The parameter file, read (base/input.h: three passes, strict in the last)
// into the parts' settings: scene, regions, bond filters, blocks with their
// material and damage model instances, coupling, conditions, computes, the
// solver and the output. Every registered time integrator parses its own
// keys (so that their errors show whichever is chosen); the one of
// Solver/Type runs.

#include <perideal/adaptivity/adaptivity_parameters.h>
#include <perideal/base/input.h>
#include <perideal/compute/region_compute.h>
#include <perideal/conditions/boundary_conditions.h>
#include <perideal/contact/contact.h>
#include <perideal/damage/initial_damage.h>
#include <perideal/geometry/region.h>
#include <perideal/geometry/scene.h>
#include <perideal/model/block.h>
#include <perideal/neighborhood/bond_filter.h>
#include <perideal/output/output.h>
#include <perideal/solver/implicit.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace perideal
{
  class TimeIntegrator;

  /// The user-chosen names of a parameter file (and the model of each).
  struct DeckNames
  {
    std::vector<std::string>           regions, bond_filters, initial_damage, blocks, conditions, computes,
      contact_interactions, solver_stages;
    std::map<std::string, std::string> materials, damage_models, contact_models; // name -> model ("" unknown yet)
  };

  /// Declares every section of the parameter file for the given names.
  void
  declare_parameters(ParameterHandler &prm, const DeckNames &names);

  /// The full parameter reference, with one example entry of every model.
  void
  print_parameter_reference(std::ostream &out, const bool markdown);

  /// Solver: what every integrator shares.
  struct SolverParameters
  {
    std::string        type = "Verlet";
    double             initial_time = 0, final_time = 0;
    unsigned int       requested_steps     = 0;
    double             energy_growth_limit = 0;
    bool               track_dissipation   = true; // Solver/Track dissipated energy
    ImplicitParameters implicit;                     // Solver/Implicit: Newton and the linear solvers
  };

  /// A solver that runs after the one of Solver (Solver stages/NAME;
  /// Peridigm's Solver2, Solver3, ...): it starts where the one before ended,
  /// from its state, and continues its step numbers and output series.
  struct SolverStage
  {
    SolverStage();
    SolverStage(SolverStage &&) noexcept;
    ~SolverStage();

    std::string                     name;
    SolverParameters                solver; // initial_time: set when the stage starts
    std::unique_ptr<TimeIntegrator> integrator;
    int output_frequency = -1, globals_frequency = -1; // -1: Output's
    /// After a QuasiStatic solver: whether this stage starts with the
    /// velocity of its last load step, (u_n - u_{n-1}) / dt (Peridigm's
    /// hand-off), or with the free points at rest (Velocity after quasistatic).
    bool velocity_of_load_step = false;
  };

  /// Coupling with continuum blocks (doc/coupling.md).
  struct CouplingParameters
  {
    /// energy: the blended energy (symmetric, exact global balance, ghost
    /// forces); force: force-based blending, free of ghost forces
    /// (doc/coupling.md).
    enum class Scheme
    {
      energy,
      force
    };
    Scheme scheme               = Scheme::energy;
    double blending_width       = 1;  // in horizons
    int    virtual_point_levels = -1; // -1: auto
  };

  /// Temperature (thermal strain, doc/thermal.md): T(x, y, z, t) and T_ref.
  struct TemperatureParameters
  {
    std::string function; // empty: no temperature field
    double      reference = 0;
  };

  struct Deck
  {
    Deck();
    ~Deck();

    Scene                                          scene;
    std::map<std::string, std::unique_ptr<Region>> regions;
    std::vector<BondFilter>                        bond_filters;
    std::vector<InitialDamage>                     initial_damage;
    std::vector<Block>                             blocks;
    bool                                           has_continuum = false;
    CouplingParameters                             coupling;
    AdaptivityParameters                           adaptivity;
    TemperatureParameters                          temperature;
    ContactParameters                              contact;
    std::vector<BoundaryCondition>                 conditions;
    std::vector<RegionCompute>                     computes;
    // The running solver: Solver's (Solver/Type, parsed), then each of stages in turn.
    SolverParameters                               solver;
    std::unique_ptr<TimeIntegrator>                integrator;
    std::vector<SolverStage>                       stages; // Solver stages, in the order of their Names
    OutputWriter                                   output;
  };

  /// Reads @p parameter_file into @p deck; an Error names the key or line.
  void
  read_deck(const std::string &parameter_file, Deck &deck);
} // namespace perideal
