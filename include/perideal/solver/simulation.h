#pragma once
// The simulation: reads the parameter file, builds mesh, points, bonds and
// models, and runs the explicit velocity-Verlet integrator with lumped mass.
// One gather/evaluate routine (compute_forces) serves every step, the
// initial state and the energy checks.

#include <perideal/base/best_point.h>
#include <perideal/base/input.h>
#include <perideal/base/memory.h>
#include <perideal/compute/region_compute.h>
#include <perideal/conditions/boundary_conditions.h>
#include <perideal/continuum/continuum_field.h>
#include <perideal/continuum/linear_elasticity.h>
#include <perideal/damage/damage_model.h>
#include <perideal/discretization/point_cloud.h>
#include <perideal/geometry/region.h>
#include <perideal/geometry/scene.h>
#include <perideal/material/material.h>
#include <perideal/neighborhood/bond_filter.h>
#include <perideal/neighborhood/bonds.h>
#include <perideal/output/output.h>
#include <perideal/solver/coupled_tangent.h>
#include <perideal/solver/implicit.h>
#include <perideal/solver/tangent.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/hp/fe_collection.h>
#include <deal.II/lac/trilinos_precondition.h>

#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace perideal
{
  /// The user-chosen names of a parameter file (and the model of each).
  struct DeckNames
  {
    std::vector<std::string>           regions, bond_filters, blocks, conditions, computes;
    std::map<std::string, std::string> materials, damage_models; // name -> model ("" unknown yet)
  };

  /// Declares every section of the parameter file for the given names.
  void
  declare_parameters(ParameterHandler &prm, const DeckNames &names);

  /// The full parameter reference, with one example entry of every model.
  void
  print_parameter_reference(std::ostream &out, const bool markdown);

  struct Block
  {
    std::string               name;
    std::vector<unsigned int> material_ids;
    std::string               region;
    std::string               material_name, damage_name;
    double                    horizon = 0;
    bool                      continuum = false; // FE cells; its points are virtual points
    unsigned int              fe_degree = 1;
    std::unique_ptr<LinearElasticity> elasticity; // continuum blocks only
    std::unique_ptr<Material>    material;
    std::unique_ptr<DamageModel> damage;
    std::vector<unsigned int>    points; // owned points of this block (virtual points for continuum blocks)
  };

  class Simulation
  {
  public:
    Simulation(const std::string &parameter_file, const MPI_Comm comm);

    /// Sets up and prints points, bonds, memory estimate and time step.
    void
    dry_run();

    /// Sets up and integrates to the final time.
    void
    run();

  private:
    void
    read_parameters(const std::string &parameter_file);
    /// Mesh, points, bonds (rebalanced by bonds on several ranks), models.
    void
    setup();
    /// Whether @p x (in @p cell) lies in the region named @p region ("All": everywhere).
    bool
    in_region(const std::string &region, const dealii::Point<dim> &x, const CellIterator &cell) const
    {
      return region == "All" || regions.at(region)->contains(x, cell);
    }
    /// Collective: stops if a region's expression was not finite at a point
    /// it was asked about (NaN would silently put the point inside).
    void
    check_region_expressions() const;
    /// The block that claims @p cell (the first whose region or material ids
    /// hold it), -1 if none.
    int
    block_of_cell(const CellIterator &cell) const;
    /// Size checks (source/solver/size_check.cc): the built-in scene's cells,
    /// points and bonds before the mesh is made, and the mesh's (with the
    /// cells flagged for refinement) once it exists, against the memory
    /// available; an Error naming the key if too large. Collective.
    void
    check_scene_size(const AvailableMemory &available) const;
    void
    check_mesh_size(const AvailableMemory &available, const std::string &what, const std::string &cells_key,
                    const double descendants = 0) const; // > 0: every cell becomes this many
    /// The horizon key of the block with the largest horizon, for messages.
    std::string
    horizon_key() const;
    /// Collective: stops, naming the block and why, if a block of
    /// Blocks/Names claims no cell (a silent no-op otherwise).
    void
    check_blocks_have_cells() const;
    /// DoFs, point cloud and families of the current partition.
    void
    build_points_and_bonds();
    /// Removes the bonds that cross a bond filter; counts them per filter.
    void
    apply_bond_filters();
    /// Checks the families, assigns points to blocks, initializes the models.
    void
    setup_models();
    void
    apply_initial_conditions();
    void
    apply_prescribed(const double time, const double dt);
    void
    check_condition_values(const unsigned int bad_local, const double time) const;
    /// 1 + the index of the first condition whose value is not finite at one
    /// of its (owned) points at @p time; 0 if none.
    unsigned int
    first_nonfinite_condition(const double time) const;
    /// body_force (PD points) and the FE load (body forces at nodes,
    /// tractions on faces) of the load conditions at @p time (if any).
    void
    evaluate_loads(const double time);
    void
    compute_forces(const bool with_energy);
    double
    stable_time_step();
    /// The globals row and/or the field files of @p step (the error path
    /// writes both).
    void
    write_output(const unsigned int step, const double time, const bool globals = true, const bool field_files = true);
    std::vector<std::pair<std::string, double>>
    global_quantities(const unsigned int step, const double time);
    void
    print_setup_report();
    void
    print_summary(const double loop_seconds, const unsigned int steps_done);
    /// Interrupted runs (base/interrupt.h). Collective. During set-up: stops
    /// if a rank has received a signal. After a completed @p step: writes it
    /// where the output writes anything (what its output with @p n_steps did
    /// not write already), prints the summary and throws Interrupted.
    void
    stop_if_interrupted_in_setup();
    [[noreturn]] void
    stop_interrupted(const unsigned int step, const double time, const unsigned int n_steps,
                     const double loop_seconds);
    /// "point N at (x, y, z)": the first point (or FE DoF) with a
    /// non-finite value, the same on any number of ranks. Collective.
    std::string
    locate_nonfinite();
    /// The point (or FE DoF) with the largest speed (the value), the
    /// same on every rank. Collective.
    BestPoint
    fastest_point() const;
    /// Forces (and energy density) of the initial state, ghosts updated.
    void
    evaluate_initial_state();
    /// Initial energy from the globals of step 0; writes step 0 if it is an output step.
    void
    record_initial_state(const unsigned int n_steps, const double time);
    /// 1 - (intact neighbor volume)/(neighbor volume) of owned point @p i.
    double
    point_damage(const unsigned int i) const;
    /// The smallest point spacing, (cell volume)^(1/3), over the points with mass.
    double
    point_spacing() const;
    /// The largest speed of a point with mass and an intact bond (collective).
    double
    fastest_bonded_speed() const;
    /// The strain energy that bond breaking released at the current state:
    /// with the bonds of @p mask_before (the broken flags before the breaks)
    /// minus with those of now, summed over ranks. Leaves the forces and
    /// energy densities of now.
    double
    released_energy(std::vector<std::uint8_t> &mask_before);
    /// The largest stretch of the intact bonds of owned point @p i (ghosted
    /// displacement).
    double
    point_stretch(const unsigned int i) const;

    // The implicit solvers (implicit.cc).
    struct NewtonResult
    {
      unsigned int        newton_iterations = 0, linear_iterations = 0;
      double              residual = 0;
    };
    void
    run_quasistatic();
    void
    run_newmark();
    /// Tangent sparsity, prescribed DoFs, rigid-body modes (and, if
    /// @p need_supports, the check that conditions remove them).
    void
    setup_implicit(const bool need_supports);
    /// R = V (f + b) - M a on the free DoFs of the current displacement
    /// (a: Newmark's, from newmark_inertia and u_predicted); returns
    /// |R| and sets |V (f + b)| over all DoFs (the force scale).
    double
    residual(std::vector<double> &R, double &force_norm);
    /// The implicit solvers' unknowns on this rank: every owned PD DoF, or
    /// with continuum blocks the free DoFs of coupled_tangent.h.
    unsigned int
    n_unknowns() const;
    double &
    unknown(const unsigned int j);
    void
    assemble_tangent();
    /// Solves K du = R; returns the Krylov iterations.
    unsigned int
    solve_linear(const std::vector<double> &R, std::vector<double> &du);
    /// The same without a matrix (Jacobian = Matrix free).
    unsigned int
    solve_matrix_free(const std::vector<double> &R, std::vector<double> &du);
    /// The tangent's kind and size, for the reports.
    std::string
    describe_tangent() const;
    NewtonResult
    solve_newton(const unsigned int step);
    /// Newton, then break bonds and solve again while bonds break; sets
    /// last_newton (iterations summed over the solves) and last_damage_solves.
    void
    solve_step(const unsigned int step);
    /// Runs the damage models on the current state; returns the bonds (directed) broken now.
    std::size_t
    break_bonds();
    /// What the external work of an implicit step needs from its start: the
    /// supports' forces, the displacements and the loads.
    struct LoadPathState
    {
      std::vector<double> support, node_support, u, fe_u, body, load;
    };
    LoadPathState
    load_path_state() const;
    /// The work of the supports and the loads from @p start to now (trapezoid
    /// rule over the step), summed over ranks.
    double
    load_path_work(const LoadPathState &start) const;

    MPI_Comm                                  comm;
    dealii::ConditionalOStream                pcout;
    dealii::TimerOutput                       timer;
    dealii::parallel::distributed::Triangulation<dim> triangulation;
    // FE_DGQ(0)^dim on PD cells (active FE index 0), FE_Q(p)^dim on the cells
    // of continuum blocks (index p).
    dealii::hp::FECollection<dim>             fe;
    dealii::DoFHandler<dim>                   dof_handler;

    Scene                                       scene;
    std::map<std::string, std::unique_ptr<Region>> regions;
    std::vector<BondFilter>                     bond_filters;
    std::vector<std::size_t>                    filtered_bonds; // per filter: directed bonds it cut (all ranks)
    std::vector<Block>                          blocks;
    std::vector<BoundaryCondition>              conditions;
    std::vector<RegionCompute>                  computes;
    OutputWriter                                output;

    // Solver
    std::string  solver_type = "Verlet";
    ImplicitParameters implicit;
    double       initial_time = 0, final_time = 0, fixed_dt = 0, safety_factor = 0;
    unsigned int requested_steps = 0;
    double       energy_growth_limit = 0;
    bool         track_dissipation   = false; // Solver/Track dissipated energy

    // Coupling with continuum blocks (doc/coupling.md); nothing is allocated
    // without a continuum block.
    double                          blending_width       = 1; // in horizons
    int                             virtual_point_levels = -1; // -1: auto
    bool                            has_continuum        = false;
    std::unique_ptr<ContinuumField> continuum;
    std::vector<unsigned int>       virtual_points;  // owned virtual points (local index)
    std::vector<double>             point_alpha;     // PD energy weight per owned point (continuum runs)
    std::vector<double>             cell_fe_weight;  // per active cell: 1 - alpha of its centre
    std::vector<unsigned char>      cell_virtual;    // per active cell: 1 + its virtual point levels, 0: none
    std::vector<double>             u_virtual, f_virtual, node_density;
    struct NodeConstraint
    {
      unsigned int node, condition; // index into continuum->nodes
    };
    std::vector<NodeConstraint> node_constraints;
    std::vector<double>         node_constraint_force;
    std::vector<double>         node_constraint_displacement; // per node constraint: its own u (prescribed velocity)
    /// The point cloud of a run with continuum blocks: PD points and the
    /// virtual points of the FE cells within reach of them, with alpha (PD
    /// energy weight) per point and 1 - alpha per FE cell from the distance
    /// to the nearest PD point (build_points_and_bonds).
    void
    build_coupled_cloud(const std::function<int(const CellIterator &)> &block_of, const double max_horizon);
    /// Removes the bonds between two points of energy weight 0 (virtual
    /// points beyond the band): they carry no energy, and such a point needs
    /// only its bonds to weighted points to receive their reactions.
    void
    drop_unweighted_bonds();
    /// The FE field of the continuum blocks at the virtual points (U's ghosts updated first).
    void
    update_virtual_points();
    void
    setup_continuum();
    /// Per owned FE DoF: 1 if a prescribed condition holds it.
    std::vector<std::uint8_t>
    fe_prescribed_flags() const;
    bool
    is_virtual(const unsigned int i) const
    {
      return has_continuum && blocks[cloud.block[i]].continuum;
    }

    // Points, bonds and state
    PointCloud                 cloud;
    Bonds                      bonds;
    std::vector<std::uint8_t>  broken;       // per bond, only with a damage model
    std::unique_ptr<FieldStore> fields;
    VectorType                 displacement; // ghosted, dim per point
    VectorType                 velocity, force;
    std::vector<double>        energy_density;
    std::vector<double>        mass_density; // per owned point
    std::vector<double>        body_force;   // per owned point and component; empty if none
    bool                       loads_depend_on_time = false;
    std::vector<std::string>   ghosted_stage_fields;

    // Prescribed components: (point, component, condition)
    struct Constraint
    {
      unsigned int point, component, condition;
    };
    std::vector<Constraint> constraints;
    std::vector<double>     constraint_force; // internal force at the constraints, previous step
    std::vector<double>     constraint_displacement; // per constraint: its own u (prescribed velocity)
    unsigned int            bad_condition = 0; // 1 + index of a condition that gave a non-finite value
    /// The force the support of prescribed entry @p c puts on the body:
    /// m a - V f (quasistatic, no acceleration: -V f).
    double
    support_force(const Constraint &c) const;
    /// The same at an FE node: M a - F.
    double
    node_support_force(const NodeConstraint &c) const;

    // Diagnostics
    double      dt = 0, dt_stable = 0;
    double      external_work = 0, initial_energy = 0, last_strain_energy = 0, last_kinetic_energy = 0;
    double      dissipated_energy = 0; // released by broken bonds (released_energy)
    unsigned int shortened_steps  = 0; // Verlet steps shortened below the elastic step
    double      shortest_dt       = std::numeric_limits<double>::max();
    std::size_t broken_bond_count = 0; // directed entries, this rank
    double      startup_memory    = 0; // resident bytes before the scene is read
    bool        dry_run_mode      = false; // --dry-run: a scene too large prints its size estimate
    double      unbalanced_bonds  = 0; // % above the mean before rebalancing, 0: not needed
    // Per block: the critical stretch its material applies in its force loop
    // (squared_limit 0: not fused, the damage model runs its own pass).
    std::vector<StretchBreaking> fused_breaking;
    BondStretchLimits            stretch_limits; // the critical stretch of each bond, across blocks
    std::vector<std::string> warnings;
    double      setup_seconds = 0;

    // Implicit solvers only (nothing allocated for an explicit run).
    bool                      breaking_allowed = true; // false: bonds break only in break_bonds()
    std::unique_ptr<Tangent>  tangent;
    std::unique_ptr<CoupledTangent> coupled_tangent; // with continuum blocks
    bool                      symmetry_reported = false;
    std::vector<std::uint8_t> constrained_dofs; // per local DoF
    std::vector<double>       rigid_modes;      // 6 x owned DoFs, column major
    std::vector<double>       block_inverse;    // matrix free: 9 per owned point
    std::unique_ptr<dealii::TrilinosWrappers::PreconditionAMG> amg; // of the current solve
    bool                      rebuild_amg    = true;
    unsigned int              amg_iterations = 0; // Krylov iterations with a fresh hierarchy
    bool                      use_finite_differences = false;
    double                    fd_step                = 0;
    NewtonResult              last_newton;
    unsigned int              last_damage_solves = 0;
    double                    newmark_inertia = 0; // 1/(beta dt^2); 0: quasistatic
    std::vector<double>       u_predicted;         // Newmark predictor, owned DoFs
    std::vector<double>       fe_u_predicted;      // Newmark predictor, owned FE DoFs (continuum blocks)
    std::vector<double>       fe_acceleration;     // Newmark, owned FE DoFs (continuum blocks)
    std::vector<double>       acceleration;        // Newmark, owned DoFs
  };
} // namespace perideal
