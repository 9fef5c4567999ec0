#pragma once
// What a run reports: the computes' points, the globals row of a step (the
// energies, broken bonds, the computes, the integrator's own columns), the
// field files of an output step, the set-up report and the closing summary.

#include <perideal/compute/region_compute.h>
#include <perideal/discretization/point_cloud.h>
#include <perideal/neighborhood/bonds.h>
#include <perideal/output/output.h>
#include <perideal/output/output_field.h>
#include <perideal/model/state.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/dofs/dof_handler.h>

#include <boost/signals2/connection.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace perideal
{
  struct Deck;
  class Discretization;
  class ForceModel;
  class Coupling;
  class ConditionSet;
  class TimeIntegrator;
  class ContinuumField;
  struct Fragments;

  class Postprocess
  {
  public:
    Postprocess(Deck &deck, Discretization &discretization, ForceModel &model, ConditionSet &conditions,
                MechanicalState &state, RunRecord &record, const MPI_Comm comm, dealii::ConditionalOStream &pcout,
                dealii::TimerOutput &timer);

    /// The computes' points and nodes (each must hold one). Collective.
    void
    setup(Coupling *coupling);

    /// The globals row of the current state (energies from the last
    /// evaluation with energy). Sets record.last_kinetic_energy and
    /// last_strain_energy. Collective.
    std::vector<std::pair<std::string, double>>
    global_quantities(const unsigned int step, const double time);
    /// Kinetic and strain energy of the current state (strain energy from
    /// the last evaluation with energy), summed over ranks. Collective.
    std::pair<double, double>
    energies() const;
    /// The globals row and/or the field files of @p step. Collective.
    void
    write_output(const unsigned int step, const double time, const bool globals = true, const bool field_files = true);

    void
    print_setup_report();
    void
    print_summary(const double loop_seconds, const unsigned int steps_done);

    /// The output series, the computes' rates and the fragments so far
    /// (checkpoint.h).
    void
    save(CheckpointWriter &out) const;
    void
    load(CheckpointReader &in);

    OutputWriter &output;
    // The steps of the solvers before the running one (Solver stages): the
    // integrators count their own steps, the files and rows go on.
    unsigned int step_offset = 0;

  private:
    /// What computes and output fields read, now.
    ComputeData
    compute_data() const;

    /// This rank's points and continuum cells for Output/Field format =
    /// exodus, as cells of @p dofs.
    OutputWriter::ExodusMesh
    exodus_mesh(const dealii::DoFHandler<dim> &dofs) const;

    /// The DoFs the field files are written through: FE_DGQ(0) on PD cells
    /// (a point's values), FE_Q(p) on FE cells. The discretization's until a
    /// cell converts; then a numbering of their own, made again when the
    /// converted cells or the mesh have changed since it was made (the
    /// discretization's keeps FE_Q on a converted cell: is_fe_cell()).
    /// Collective.
    const dealii::DoFHandler<dim> &
    written_dofs();
    /// written_fe_dofs for the numbering just made.
    void
    map_fe_dofs();
    std::unique_ptr<dealii::DoFHandler<dim>>        own_written_dofs;
    // Per DoF of an FE cell that own_written_dofs owns: its index in the
    // discretization's numbering and in the written one (made once per
    // numbering, read by every nodal field of every output step).
    std::vector<std::pair<dealii::types::global_dof_index, dealii::types::global_dof_index>> written_fe_dofs;
    std::vector<std::uint8_t>                       written_dofs_converted; // converted when they were numbered
    bool                                            written_dofs_numbered = false; // since the mesh changed
    std::vector<boost::signals2::scoped_connection> written_dofs_connections;

    /// The summary's line on an adaptive run's time (this run's timer):
    /// the loop split into stepping, the indicator's checks and the
    /// conversions, and one conversion against one step.
    void
    report_conversion_cost(const double loop_seconds, const unsigned int steps_done) const;

    /// Adds the rows of @p fragments to <base name>.fragments.csv and writes
    /// it whole (rank 0), as the other output files.
    void
    write_fragments(const Fragments &fragments, const unsigned int step, const double time);
    std::string fragments_csv; // the file's text so far (rank 0)
    std::size_t last_fragments      = 0;
    double      last_fragments_time = 0;
    bool        fragments_found     = false; // at some field step

    Deck                       &deck;
    Discretization             &discretization;
    ForceModel                 &model;
    ConditionSet               &conditions;
    MechanicalState            &state;
    RunRecord                  &record;
    MPI_Comm                    comm;
    dealii::ConditionalOStream &pcout;
    dealii::TimerOutput        &timer;
    Coupling                   *coupling      = nullptr;
    ContinuumField             *continuum     = nullptr; // coupling's FE field
    bool                        has_continuum = false;
    unsigned int                setups        = 0; // setup() calls: after the first, a rebuild (conversion)
    std::vector<RegionCompute> &computes;
    const PointCloud           &cloud;
    const Bonds                &bonds;
    std::vector<OutputVariable> fields; // the ones Output/Variables asks for
  };
} // namespace perideal
