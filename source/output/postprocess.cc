// What a run reports (postprocess.h): globals, field files, set-up report
// and closing summary.

#include <perideal/base/expression.h>
#include <perideal/base/format.h>
#include <perideal/base/memory.h>
#include <perideal/compute/fragments.h>
#include <perideal/conditions/condition_set.h>
#include <perideal/continuum/coupling.h>
#include <perideal/model/force_model.h>
#include <perideal/contact/contact.h>
#include <perideal/output/postprocess.h>
#include <perideal/output/checkpoint.h>
#include <perideal/simulation/deck.h>
#include <perideal/solver/time_integrator.h>

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_tools.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <memory>
#include <set>
#include <sstream>
#include <utility>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    /// A globals row's energies, and their balance, must be doubles: one that
    /// overflowed would be written as inf or nan with exit 0. The row holds
    /// global sums, the same on every rank, so every rank stops alike.
    void
    check_energies_finite(const std::vector<std::pair<std::string, double>> &row)
    {
      // Each energy column and what most likely drives it out of range.
      static const std::vector<std::pair<std::string, std::string>> causes{
        {"kinetic_energy", "a time step beyond the stable one, or an extreme initial velocity"},
        {"strain_energy", "extreme material constants or prescribed displacements"},
        {"external_work", "an extreme boundary condition or body force"},
        {"contact_energy", "an extreme contact Spring constant"},
        {"contact_dissipation", "an extreme contact Spring constant or Friction coefficient"},
        {"material_dissipation", "a material constant out of range (e.g. Yield stress, Relaxation time)"},
        {"released_energy", "extreme material constants"},
        {"conversion_energy", "cells converted to peridynamics under extreme strain"}};
      double step = 0, time = 0, balance = 0;
      for (const auto &[name, value] : row)
        {
          if (name == "step")
            step = value;
          else if (name == "time")
            time = value;
          for (const auto &[energy, cause] : causes)
            if (name == energy)
              {
                AssertThrow(std::isfinite(value),
                            ExcMessage("at step " + std::to_string(std::llround(step)) + " (t = " + sci(time, 6) +
                                       ") the globals' " + name + " is " + sci(value) +
                                       ": it has left the range of a double (1.8e308); likely cause: " + cause));
                balance += name == "external_work" || name == "conversion_energy" ? -value : value;
              }
        }
      AssertThrow(std::isfinite(balance),
                  ExcMessage("at step " + std::to_string(std::llround(step)) + " (t = " + sci(time, 6) +
                             ") the energy balance (kinetic + strain + dissipated - external work) is " +
                             sci(balance) + ": its energies, each finite, sum beyond the range of a double "
                             "(1.8e308); likely cause: extreme material constants, loads or velocities"));
    }
  } // namespace

  Postprocess::Postprocess(Deck &deck, Discretization &discretization, ForceModel &model, ConditionSet &conditions,
                           MechanicalState &state, RunRecord &record, const MPI_Comm comm, ConditionalOStream &pcout,
                           TimerOutput &timer)
    : output(deck.output)
    , deck(deck)
    , discretization(discretization)
    , model(model)
    , conditions(conditions)
    , state(state)
    , record(record)
    , comm(comm)
    , pcout(pcout)
    , timer(timer)
    , computes(deck.computes)
    , cloud(discretization.cloud)
    , bonds(discretization.bonds)
  {
    // The fields Output/Variables asks for, in the files' order. A model's
    // field needs a block whose model has it (zeros everywhere would look
    // like a result).
    const std::vector<PointField> model_fields = model_output_fields();
    for (const auto &f : model_fields)
      AssertThrow(!output.wants(f.output_name) || model.field(f.name),
                  ExcMessage("Output/Variables: '" + f.output_name + "' is a field of " +
                             models_with_output(f.output_name) + ", and no block of this scene uses " +
                             "such a model: remove it from Output/Variables"));
    for (auto &v : output_variables(model_fields))
      if (output.wants(v.name))
        fields.push_back(std::move(v));
    // A compute of a model's field (Von Mises stress) likewise: it would be a column of zeros.
    for (const auto &compute : computes)
      for (const auto &f : model_fields)
        AssertThrow(compute.variable != f.output_name || model.field(f.name),
                    ExcMessage("Computes/" + compute.name + "/Variable: '" + f.output_name + "' is a field of " +
                               models_with_output(f.output_name) + ", and no block of this scene uses " +
                               "such a model: remove the compute"));
  }

  ComputeData
  Postprocess::compute_data() const
  {
    return {cloud,
            bonds,
            state,
            model,
            continuum,
            coupling ? &coupling->node_density : nullptr,
            Utilities::MPI::this_mpi_process(comm)};
  }

  void
  Postprocess::setup(Coupling *coupling_)
  {
    coupling      = coupling_;
    continuum     = coupling ? &coupling->continuum : nullptr;
    has_continuum = coupling != nullptr;
    const bool rebuild = setups++ > 0;
    for (auto &compute : computes)
      {
        // The points as before a conversion where they are unchanged.
        compute.points = discretization.points_in_region(compute.region, compute.points);
        compute.nodes.clear();
        if (has_continuum)
          for (unsigned int k = 0; k < continuum->nodes.size(); ++k)
            {
              const auto &node = continuum->nodes[k];
              if (compute.uses_node(node.component) && discretization.in_region(compute.region, node.x, node.cell))
                compute.nodes.push_back(k);
            }
        // Over nothing, a Minimum is +1.8e308, a Mean 0: numbers that look
        // like results. A compute over an empty region is a mistake; after a
        // conversion, one the set-up could not see: a region that held only
        // FE nodes (a face) of cells that turned peridynamic, whose points
        // sit at the cells' centres.
        const std::string what = "' holds no point" + std::string(has_continuum ? " or FE node" : "") +
                                 " of the body, so '" + compute.operation + "' of " + compute.variable +
                                 " over it has no value: ";
        AssertThrow(Utilities::MPI::sum(compute.points.size() + compute.nodes.size(), comm) > 0,
                    ExcMessage("Computes/" + compute.name + "/Region: " +
                               (rebuild ? "after a conversion (Adaptivity) the region '" + compute.region + what +
                                            "the cells whose FE nodes it held turned peridynamic, and their points "
                                            "sit at the cells' centres. Make Discretization/Regions/" +
                                            compute.region + " reach the centres of the cells it measures, or keep "
                                            "those cells in a block that does not convert" :
                                          "the region '" + compute.region + what + "check Discretization/Regions/" +
                                            compute.region + " against the mesh's extent")));
      }
  }

  std::pair<double, double>
  Postprocess::energies() const
  {
    double ke = 0, se = 0;
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      {
        const double *v = state.velocity.begin() + dim * i;
        ke += 0.5 * state.mass_density[i] * cloud.volume[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        // Force blending: the PD energy of the PD points and the FE energy of
        // the FE cells (a virtual point's PD energy is not weighted away).
        if (!discretization.force_blending || !discretization.is_virtual(i))
          se += state.energy_density[i] * cloud.volume[i];
      }
    ke = Utilities::MPI::sum(ke, comm);
    se = Utilities::MPI::sum(se, comm);
    if (has_continuum)
      {
        ke += continuum->kinetic_energy();
        se += continuum->strain_energy();
      }
    return {ke, se};
  }

  std::vector<std::pair<std::string, double>>
  Postprocess::global_quantities(const unsigned int step, const double time)
  {
    const unsigned int n          = cloud.n_owned();
    const auto [ke, se]           = energies();
    double             max_damage = 0;
    std::size_t broken_local = 0;
    if (!model.broken.empty())
      for (unsigned int i = 0; i < n; ++i)
        {
          for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
            broken_local += model.broken[b];
          max_damage = std::max(max_damage, model.point_damage(i));
        }
    record.last_kinetic_energy = ke;
    record.last_strain_energy  = se;
    max_damage         = Utilities::MPI::max(max_damage, comm);
    const double broken_bonds = Utilities::MPI::sum(double(broken_local), comm) / 2;
    std::vector<std::pair<std::string, double>> row{{"step", step + step_offset},
                                                    {"time", time},
                                                    {"kinetic_energy", ke},
                                                    {"strain_energy", se},
                                                    {"external_work", record.external_work},
                                                    {"broken_bonds", broken_bonds},
                                                    {"max_damage", max_damage}};
    if (const Contact *contact = model.contact_forces())
      {
        record.last_contact_energy = Utilities::MPI::sum(contact->energy, comm);
        row.emplace_back("contact_energy", record.last_contact_energy);
        row.emplace_back("contact_dissipation", record.contact_dissipation);
      }
    model.rigid.add_globals(row, state.displacement.begin(), state.velocity.begin());
    if (deck.adaptivity.active())
      {
        // The PD region as it grows (doc/adaptivity.md).
        double pd_points = 0;
        for (unsigned int i = 0; i < n; ++i)
          pd_points += !discretization.is_virtual(i) && !cloud.is_extra(i);
        row.emplace_back("pd_points", Utilities::MPI::sum(pd_points, comm));
        row.emplace_back("bonds", Utilities::MPI::sum(double(bonds.n_bonds()), comm));
        row.emplace_back("conversion_energy", record.conversion_energy);
      }
    // Only a scene with a dissipating material gets the column.
    if (model.field_store().tracks_dissipation())
      {
        record.material_dissipation =
          Utilities::MPI::sum(model.field_store().dissipated_energy(cloud.volume, n), comm);
        row.emplace_back("material_dissipation", record.material_dissipation);
      }
    // With Solver/Track dissipated energy: the energy bond damage has
    // released so far (the summary's "dissipated energy"), so that a row's
    // energies balance without the summary.
    if (deck.solver.track_dissipation && !model.broken.empty())
      row.emplace_back("released_energy", record.dissipated_energy);
    const ComputeData data = compute_data();
    for (auto &compute : computes)
      {
        const double value = compute.evaluate(data, time, comm);
        row.emplace_back(compute.name, value);
        if (compute.rate)
          row.emplace_back(compute.name + "_rate", compute.rate_of(value, time));
      }
    {
      // A Reference that is NaN somewhere would write nan in every row.
      std::vector<const Expression *> references;
      for (const auto &compute : computes)
        references.push_back(compute.reference.get());
      check_finite(references, comm);
    }
    deck.integrator->add_globals(row);
    check_energies_finite(row);
    return row;
  }

  void
  Postprocess::write_output(const unsigned int step, const double time, const bool globals, const bool field_files)
  {
    TimerOutput::Scope t(timer, "output");
    // The CSV row goes to disk after the step's .pvtu and .pvd: a run killed
    // in between leaves a CSV that does not run ahead of the field series.
    std::vector<std::pair<std::string, double>> row;
    if (globals)
      row = global_quantities(step, time);
    if (!field_files)
      {
        if (globals)
          output.write_globals(row, comm);
        return;
      }

    const unsigned int                           n    = cloud.n_owned();
    ComputeData                                  data = compute_data();
    Fragments                                    fragments;
    if (output.fragments || output.wants("Fragment"))
      {
        fragments = find_fragments(cloud, bonds, model.broken, model.blocks, state.mass_density, state.velocity, comm);
        data.fragment         = &fragments.number;
        last_fragments        = fragments.count;
        last_fragments_time   = time;
        fragments_found       = true;
      }
    std::vector<std::unique_ptr<Vector<double>>> cell_storage;
    std::vector<OutputWriter::CellField>         cell_fields;
    std::vector<std::unique_ptr<VectorType>>     vector_storage;
    std::vector<OutputWriter::VectorField>       vector_fields;
    std::vector<types::global_dof_index>         dofs(dim);
    const DoFHandler<dim>                       &written    = written_dofs();
    const bool                                   renumbered = &written != &discretization.dof_handler;
    // On FE cells a vector takes its nodal values, with the ghosts the FE
    // cells' output needs.
    IndexSet relevant;
    if (has_continuum)
      DoFTools::extract_locally_relevant_dofs(written, relevant);
    // A symmetric tensor's 9 components from its 6 (xx yy zz xy yz xz).
    static constexpr unsigned int symmetric[9] = {0, 3, 5, 3, 1, 4, 5, 4, 2};
    for (const auto &[name, documentation, field] : fields)
      if (!field->nodal())
        {
          const unsigned int n_stored = field->n_components();
          const unsigned int n_written = n_stored == 6 ? 9 : n_stored;
          OutputWriter::CellField cells{name, {}};
          for (unsigned int c = 0; c < n_written; ++c)
            {
              const unsigned int stored = n_stored == 6 ? symmetric[c] : c;
              cell_storage.push_back(std::make_unique<Vector<double>>(discretization.triangulation.n_active_cells()));
              for (unsigned int i = 0; i < n; ++i)
                if (!discretization.is_virtual(i) || field->at_virtual_points())
                  (*cell_storage.back())[cloud.cell[i]->active_cell_index()] = field->value(data, i, stored);
              cells.components.push_back(cell_storage.back().get());
            }
          cell_fields.push_back(std::move(cells));
        }
      else
        {
          vector_storage.push_back(has_continuum ?
                                     std::make_unique<VectorType>(written.locally_owned_dofs(), relevant, comm) :
                                     std::make_unique<VectorType>(written.locally_owned_dofs(), comm));
          VectorType &out = *vector_storage.back();
          for (unsigned int i = 0; i < n; ++i)
            if (!discretization.is_virtual(i))
              {
                on(written, cloud.cell[i])->get_dof_indices(dofs);
                for (unsigned int d = 0; d < dim; ++d)
                  out(dofs[d]) = field->value(data, i, d);
              }
          if (has_continuum)
            {
              VectorType  fe_numbered;
              VectorType &fe = renumbered ? fe_numbered : out;
              if (renumbered)
                fe_numbered.reinit(continuum->U); // its layout, zeroed
              for (unsigned int k = 0; k < continuum->nodes.size(); ++k)
                fe.local_element(continuum->nodes[k].local) = field->node_value(data, k);
              continuum->hanging.distribute(fe);
              fe.update_ghost_values();
              if (renumbered)
                {
                  for (const auto &[from, to] : written_fe_dofs)
                    out(to) = fe(from);
                  out.update_ghost_values();
                }
            }
          vector_fields.emplace_back(name, &out);
        }

    // The cells of points (virtual points too) and of continuum blocks.
    std::vector<bool> written_cells(discretization.triangulation.n_active_cells(), false);
    for (unsigned int i = 0; i < n; ++i)
      written_cells[cloud.cell[i]->active_cell_index()] = true;
    if (has_continuum)
      for (const auto &cell : discretization.dof_handler.active_cell_iterators())
        if (cell->is_locally_owned() && discretization.is_fe_cell(cell))
          written_cells[cell->active_cell_index()] = true;
    const OutputWriter::ExodusMesh exodus_mesh = output.exodus ? this->exodus_mesh(written) : OutputWriter::ExodusMesh();
    output.write_fields(written, written_cells, cell_fields, vector_fields, step + step_offset,
                        time, comm, &exodus_mesh, row);
    // After the step's field files, before its globals row (README, Output).
    if (output.fragments)
      write_fragments(fragments, step + step_offset, time);
    if (globals)
      output.write_globals(row, comm);
  }

  const DoFHandler<dim> &
  Postprocess::written_dofs()
  {
    const std::vector<std::uint8_t> &converted = discretization.converted;
    if (!Utilities::MPI::logical_or(std::find(converted.begin(), converted.end(), 1) != converted.end(), comm))
      return discretization.dof_handler;
    if (own_written_dofs == nullptr)
      {
        own_written_dofs = std::make_unique<DoFHandler<dim>>(discretization.triangulation);
        written_dofs_connections =
          on_mesh_change(discretization.triangulation, [this]() { written_dofs_numbered = false; });
      }
    if (Utilities::MPI::logical_or(!written_dofs_numbered || written_dofs_converted != converted, comm))
      {
        for (const auto &cell : own_written_dofs->active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const CellIterator fe_cell = on(discretization.dof_handler, cell);
              cell->set_active_fe_index(discretization.is_fe_cell(fe_cell) ? fe_cell->active_fe_index() : 0);
            }
        own_written_dofs->distribute_dofs(discretization.fe);
        map_fe_dofs();
        written_dofs_converted = converted;
        written_dofs_numbered  = true;
      }
    return *own_written_dofs;
  }

  void
  Postprocess::map_fe_dofs()
  {
    // Each owned DoF of the written numbering lies on an owned FE cell.
    const IndexSet                      &owned = own_written_dofs->locally_owned_dofs();
    std::vector<std::uint8_t>            mapped(owned.n_elements(), 0);
    std::vector<types::global_dof_index> from, to;
    written_fe_dofs.clear();
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && discretization.is_fe_cell(cell))
        {
          from.resize(cell->get_fe().n_dofs_per_cell());
          to.resize(from.size());
          cell->get_dof_indices(from);
          on(*own_written_dofs, cell)->get_dof_indices(to);
          for (unsigned int j = 0; j < from.size(); ++j)
            if (owned.is_element(to[j]) && !std::exchange(mapped[owned.index_within_set(to[j])], 1))
              written_fe_dofs.emplace_back(from[j], to[j]);
        }
  }

  OutputWriter::ExodusMesh
  Postprocess::exodus_mesh(const DoFHandler<dim> &dofs) const
  {
    OutputWriter::ExodusMesh mesh;
    // Element block ids: the blocks' material ids (an Exodus mesh's block
    // ids), as Peridigm numbers its blocks, where each block has one of its
    // own; otherwise the blocks' order from 1.
    std::set<unsigned int> ids;
    bool                   own_ids = true;
    for (const Block &block : discretization.blocks)
      own_ids = own_ids && block.material_ids.size() == 1 && block.material_ids[0] > 0 &&
                ids.insert(block.material_ids[0]).second;
    for (unsigned int b = 0; b < discretization.blocks.size(); ++b)
      {
        const Block &block = discretization.blocks[b];
        mesh.blocks.push_back({block.name, own_ids ? int(block.material_ids[0]) : int(b + 1), block.continuum});
      }
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (!discretization.is_virtual(i))
        {
          mesh.point_cells.push_back(on(dofs, cloud.cell[i]));
          mesh.point_X.insert(mesh.point_X.end(), &cloud.X[dim * i], &cloud.X[dim * i] + dim);
          mesh.point_block.push_back(cloud.block[i]);
          mesh.point_id.push_back(cloud.gid[i] + 1);
        }
    mesh.point_ids_end = cloud.n_global(); // virtual points too: the continuum's ids follow
    if (has_continuum)
      for (const auto &cell : discretization.dof_handler.active_cell_iterators())
        if (cell->is_locally_owned() && discretization.is_fe_cell(cell))
          {
            mesh.fe_cells.push_back(on(dofs, cell));
            mesh.fe_block.push_back(discretization.block_of_cell(cell));
          }
    return mesh;
  }

  void
  Postprocess::write_fragments(const Fragments &fragments, const unsigned int step, const double time)
  {
    if (Utilities::MPI::this_mpi_process(comm) != 0)
      return;
    std::ostringstream file;
    if (fragments_csv.empty())
      file << "step,time,fragment,points,mass,velocity_x,velocity_y,velocity_z,kinetic_energy\n";
    file << std::setprecision(output.globals_digits);
    for (std::size_t f = 0; f < fragments.rows.size(); ++f)
      {
        const Fragments::Row &row = fragments.rows[f];
        file << step << ',' << time << ',' << f << ',' << row.points << ',' << row.mass;
        for (unsigned int d = 0; d < dim; ++d)
          file << ',' << row.momentum[d] / row.mass;
        file << ',' << row.kinetic_energy << '\n';
      }
    // Written whole through a temporary file, as the globals CSV: a run
    // stopped at any moment leaves no half-written row.
    fragments_csv += file.str();
    write_file_atomically(output.directory + "/" + output.base_name + ".fragments.csv", fragments_csv);
  }

  void
  Postprocess::print_setup_report()
  {
    const double bonds_global = Utilities::MPI::sum(double(bonds.n_bonds()), comm);
    std::size_t  min_family = std::numeric_limits<std::size_t>::max(), max_family = 0;
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      {
        const std::size_t s = bonds.offsets[i + 1] - bonds.offsets[i];
        min_family          = std::min(min_family, s);
        max_family          = std::max(max_family, s);
      }
    min_family = Utilities::MPI::min(min_family, comm);
    max_family = Utilities::MPI::max(max_family, comm);
    const double ghosts = Utilities::MPI::sum(double(cloud.n_local() - cloud.n_owned()), comm);

    // What this run holds, by part (all ranks).
    const double bond_bytes = bonds.neighbor.capacity() * sizeof(unsigned int) +
                              bonds.offsets.capacity() * sizeof(std::size_t) + model.broken.capacity() +
                              model.damage.capacity() * sizeof(double) +
                              bonds.volume_fraction.capacity() * sizeof(float) + bonds.family.capacity();
    const double point_bytes =
      cloud.X.capacity() * sizeof(double) + cloud.volume.capacity() * sizeof(double) +
      cloud.block.capacity() * sizeof(unsigned short) + cloud.key.capacity() * sizeof(PointKey) +
      cloud.gid.capacity() * sizeof(types::global_dof_index) + cloud.cell.capacity() * sizeof(CellIterator) +
      state.displacement.memory_consumption() + state.velocity.memory_consumption() + state.force.memory_consumption() +
      model.field_memory() + state.mass_density.capacity() * sizeof(double);
    const double mesh_bytes = discretization.triangulation.memory_consumption() + discretization.dof_handler.memory_consumption();
    const double sum_bond   = Utilities::MPI::sum(bond_bytes, comm);
    const double sum_point  = Utilities::MPI::sum(point_bytes, comm);
    const double sum_mesh   = Utilities::MPI::sum(mesh_bytes, comm);

    pcout << "PeriDeal set-up on " << Utilities::MPI::n_mpi_processes(comm) << " rank(s)\n"
          << "  points:            " << cloud.n_global() << " (nonlocal ghosts: " << ghosts << ")\n"
          << "  bonds:             " << std::setprecision(12) << bonds_global
          << (cloud.n_global() == 0 ? std::string(" (no points)") :
                                      " (directed; family size " + std::to_string(min_family) + " to " +
                                        std::to_string(max_family) + ")")
          << "\n";
    if (cloud.periodicity.any())
      {
        pcout << "  periodic:         ";
        for (unsigned int d = 0; d < dim; ++d)
          if (cloud.periodicity.length[d] > 0)
            pcout << " " << "xyz"[d] << " (period " << cloud.periodicity.length[d] << ")";
        pcout << "\n";
      }
    for (unsigned int f = 0; f < deck.bond_filters.size(); ++f)
      pcout << "  bond filter '" << deck.bond_filters[f].name << "': " << discretization.filtered_bonds[f] << " directed bonds cut"
            << (discretization.filtered_bonds[f] == 0 ? " (none: check its corner, vectors and lengths; the side runs along "
                                         "Bottom unit vector x Normal, as in Peridigm)" :
                                         "")
            << "\n";
    for (unsigned int d = 0; d < deck.initial_damage.size(); ++d)
      pcout << "  initial damage '" << deck.initial_damage[d].name
            << "': " << discretization.initially_broken_bonds[d] << " directed bonds start broken\n";
    if (Utilities::MPI::n_mpi_processes(comm) > 1)
      {
        // The bond loops dominate a step: bonds per rank is the load balance.
        const auto minmax = Utilities::MPI::min_max_avg(double(bonds.n_bonds()), comm);
        pcout << "  bonds per rank:    " << std::setprecision(12) << minmax.min << " to " << minmax.max
              << " (the largest " << sci(100 * (minmax.max / minmax.avg - 1), 3) << "% above the mean";
        if (discretization.unbalanced_bonds > 0)
          pcout << "; " << sci(discretization.unbalanced_bonds, 3) << "% with equal cells per rank: repartitioned by bonds";
        pcout << ")\n";
      }
    for (const auto &b : deck.blocks)
      if (b.continuum)
        pcout << "  block '" << b.name << "': continuum FE_Q(" << b.fe_degree << "), material '" << b.material_name
              << "' (" << b.continuum_model->describe() << "), " << Utilities::MPI::sum(b.points.size(), comm) << " virtual points\n";
      else if (b.rigid)
        {
          const auto &bodies = model.rigid.bodies;
          const auto  body   = std::find_if(bodies.begin(), bodies.end(), [&](const auto &r) { return r.name == b.name; });
          pcout << "  block '" << b.name << "': rigid, " << body->n_points << " points, mass " << sci(body->mass, 6)
                << " (material '" << b.material_name << "': its density)\n";
        }
      else
        pcout << "  block '" << b.name << "': " << Utilities::MPI::sum(b.points.size(), comm)
              << " points, material '" << b.material_name << "', horizon " << sci(b.horizon)
              << (b.damage ? ", damage: " + b.damage->describe() : std::string(", no damage")) << "\n";
    // The constrained DoFs each rank owns (its constraints also hold its ghosts').
    std::size_t constrained = 0;
    if (has_continuum)
      for (const auto &line : continuum->hanging.get_lines())
        constrained += discretization.dof_handler.locally_owned_dofs().is_element(line.index);
    if (has_continuum)
      pcout << "  finite elements:   " << continuum->n_global_dofs << " DoFs (hanging-node constraints "
            << Utilities::MPI::sum(constrained, comm) << "), blending band "
            << sci(deck.coupling.blending_width, 3) << " horizons, virtual point levels "
            << (deck.coupling.virtual_point_levels < 0 ? std::string("auto") : std::to_string(deck.coupling.virtual_point_levels)) << "\n";
    for (const auto &bc : conditions.conditions)
      {
        // Collective on every rank.
        const auto   n_fe  = std::count_if(bc.dofs.begin(), bc.dofs.end(), [&](unsigned int k) { return state.is_fe(k); });
        const auto   nodes = Utilities::MPI::sum(std::size_t(n_fe), comm);
        const auto   faces = Utilities::MPI::sum(bc.faces.size(), comm);
        const auto   point_faces = Utilities::MPI::sum(bc.point_faces.size(), comm);
        const auto   points = Utilities::MPI::sum(bc.dofs.size() - n_fe, comm);
        pcout << "  condition '" << bc.name << "': "
              << (bc.type == BoundaryCondition::Type::traction ?
                    std::to_string(faces + point_faces) + " boundary faces" +
                      (point_faces > 0 ? " (" + std::to_string(point_faces) + " of PD cells)" : std::string()) :
                    std::to_string(points) + " points" +
                      (has_continuum ? ", " + std::to_string(nodes) + " FE DoFs" : std::string()))
              << (bc.boundary_id >= 0 && bc.type == BoundaryCondition::Type::traction ?
                    " (boundary id " + std::to_string(bc.boundary_id) + ")\n" :
                    " (region '" + bc.region + "')\n");
      }
    pcout << "  memory estimate:   bonds " << mib(sum_bond) << ", point fields " << mib(sum_point)
          << ", mesh and DoFs " << mib(sum_mesh) << "; total " << mib(sum_bond + sum_point + sum_mesh)
          << " (" << sci((sum_bond + sum_point + sum_mesh) / std::max(1.0, bonds_global), 3)
          << " bytes per bond)\n";
    deck.integrator->report_setup();
    for (const auto &w : record.warnings)
      pcout << "Warning: " << w << "\n";
    pcout << std::flush;
  }

  void
  Postprocess::report_conversion_cost(const double loop_seconds, const unsigned int steps_done) const
  {
    // This run's timer (a continued run: since its restart), rank 0's.
    const auto   seconds = timer.get_summary_data(TimerOutput::total_wall_time);
    const auto   calls   = timer.get_summary_data(TimerOutput::n_calls);
    const auto   get     = [](const auto &map, const std::string &name) {
      const auto it = map.find(name);
      return it == map.end() ? 0.0 : double(it->second);
    };
    const double checks      = get(seconds, "adaptivity");
    const double conversions = get(calls, "adaptivity: conversion");
    const double converting  = get(seconds, "adaptivity: conversion");
    const double refinement  = get(seconds, "adaptivity: refinement");
    const double moves       = get(seconds, "adaptivity: rebalance");
    const double stepping    = loop_seconds - checks;
    const double per_step    = steps_done > 0 ? stepping / steps_done : 0.0;
    const auto s = [](const double x) { return sci(x, 3) + " s"; };
    pcout << "  conversions' cost:      " << s(checks) << " of the " << s(loop_seconds) << " loop: the indicator "
          << s(get(seconds, "adaptivity: indicator")) << " at " << get(calls, "adaptivity") << " checks";
    if (conversions > 0)
      pcout << ", " << conversions << " conversions " << s(converting) << " (refinement " << s(refinement)
            << ", moves between ranks " << s(moves) << ", the points, bonds and parts and the state carried over "
            << s(converting - refinement - moves) << "); one conversion " << s(converting / conversions)
            << ", as long as " << std::lround(per_step > 0 ? converting / conversions / per_step : 0.0)
            << " steps of " << s(per_step);
    pcout << "\n";
  }

  void
  Postprocess::print_summary(const double loop_seconds, const unsigned int steps_done)
  {
    const double bonds_global = Utilities::MPI::sum(double(bonds.n_bonds()), comm);
    const double peak_sum     = peak_memory_bytes_sum(comm);
    const double peak_max     = Utilities::MPI::max(peak_memory_bytes(), comm);
    const double startup_sum  = Utilities::MPI::sum(record.startup_memory, comm);
    const double startup_max  = Utilities::MPI::max(record.startup_memory, comm);
    const unsigned int ranks  = Utilities::MPI::n_mpi_processes(comm);
    const double e_ref        = std::abs(record.initial_energy) + std::abs(record.external_work);

    pcout << "\nPeriDeal summary\n"
          << "  points:                 " << cloud.n_global() << "\n"
          << "  bonds:                  " << std::setprecision(12) << bonds_global << " (directed)\n"
          << "  steps:                  " << steps_done << "\n"
          << "  wall time:              " << format_seconds(record.setup_seconds + loop_seconds)
          << " (set-up " << format_seconds(record.setup_seconds) << ", " << deck.integrator->loop_name() << " "
          << format_seconds(loop_seconds) << ")\n";
    deck.integrator->report_summary_speed(loop_seconds, steps_done);
    pcout << "  peak memory:            " << mib(peak_sum) << " over all ranks (largest rank " << mib(peak_max)
          << "); " << sci(peak_sum / std::max(1.0, bonds_global), 3) << " bytes per bond, "
          << sci(peak_sum / std::max<double>(1, cloud.n_global()), 4) << " bytes per point\n";
    pcout << "  scene memory:           " << mib(peak_sum - startup_sum)
          << " over all ranks: peak minus the start-up footprint (libraries; " << mib(startup_max)
          << " per rank); " << sci((peak_sum - startup_sum) / std::max(1.0, bonds_global), 3)
          << " bytes per bond\n";
    deck.integrator->report_summary_step();
    const bool dissipation = deck.solver.track_dissipation && !model.broken.empty();
    if (dissipation)
      pcout << "  dissipated energy:      " << sci(record.dissipated_energy, 6)
            << (model.continuous_damage() ?
                  " (released by bond damage: each step's strain energy with the damage before it minus after)\n" :
                  " (released by broken bonds: their strain energy where they broke)\n");
    if (deck.adaptivity.active())
      pcout << "  adaptivity:             " << record.conversions << " conversions, " << std::setprecision(12)
            << record.converted_cells << " cells turned peridynamic, energy jumps " << sci(record.conversion_energy, 4)
            << " in all; " << format_seconds(record.conversion_seconds) << " in checks and conversions\n";
    if (deck.adaptivity.active())
      report_conversion_cost(loop_seconds, steps_done);
    const bool material_dissipation = model.field_store().tracks_dissipation();
    if (material_dissipation)
      pcout << "  material dissipation:   " << sci(record.material_dissipation, 6)
            << " (plastic and viscous work of the materials, sum V_i D_i, at the last globals row)\n";
    const Contact *contact = model.contact_forces();
    if (contact)
      pcout << "  contact:                energy " << sci(record.last_contact_energy, 6) << ", friction work "
            << sci(record.contact_dissipation, 6) << "; the list built " << contact->builds
            << " times, search radius " << sci(contact->search_radius(), 4) << "\n";
    const bool neglecting = std::any_of(deck.blocks.begin(), deck.blocks.end(),
                                        [](const Block &b) { return b.damage && b.neglect_damage < 1; });
    const auto neglected  = Utilities::MPI::sum(model.neglected_points(), comm);
    if (neglecting)
      pcout << "  neglected points:       " << neglected
            << " (damage above their Critical damage to neglect material point: all bonds broken)\n";
    if (fragments_found)
      pcout << "  fragments:              " << last_fragments << " at t = " << sci(last_fragments_time, 6)
            << (output.fragments ? " (" + output.directory + "/" + output.base_name + ".fragments.csv)" : std::string())
            << "\n";
    // Without the release tracked, the energy broken or damaged bonds took
    // with them is in the balance: say so, lest it be read as an error.
    double damaged = 0;
    if (!dissipation)
      {
        for (std::size_t b = 0; b < model.broken.size(); ++b)
          damaged += model.broken[b] != 0 || (!model.damage.empty() && model.damage[b] > 0);
        damaged = Utilities::MPI::sum(damaged, comm) / 2;
      }
    if (e_ref > 0)
      {
        pcout << "  energy balance error:   "
              << sci((record.last_kinetic_energy + record.last_strain_energy + record.dissipated_energy +
                      record.material_dissipation + record.last_contact_energy + record.contact_dissipation -
                      record.initial_energy - record.external_work - record.conversion_energy) /
                       e_ref,
                     3)
              << " (kinetic + strain" << (contact ? " + contact + friction work" : "")
              << (dissipation ? " + dissipated" : "") << (material_dissipation ? " + material dissipation" : "")
              << " - initial - external work" << (deck.adaptivity.active() ? " - conversion jumps" : "")
              << ", relative)\n";
        if (damaged > 0)
          pcout << "                          not an error alone: it includes the energy released by the "
                << std::setprecision(12) << damaged
                << " damaged bonds, untracked; Solver/Track dissipated energy = true separates it\n";
      }
    pcout << "  warnings:               " << (record.warnings.empty() ? std::string("none") : std::to_string(record.warnings.size()))
          << "\n";
    for (const auto &w : record.warnings)
      pcout << "Warning: " << w << "\n";
    pcout << std::flush;
    timer.print_summary();
    // Where ranks wait for each other: the spread of every section over ranks.
    if (ranks > 1)
      timer.print_wall_time_statistics(comm);
  }

  void
  Postprocess::save(CheckpointWriter &out) const
  {
    output.save(out);
    out.section("postprocess");
    out.put(computes.size());
    for (const RegionCompute &c : computes)
      c.save(out);
    out.put(fragments_csv);
    out.put(last_fragments);
    out.put(last_fragments_time);
    out.put(fragments_found);
    out.put(step_offset);
  }

  void
  Postprocess::load(CheckpointReader &in)
  {
    output.load(in);
    in.section("postprocess");
    in.expect(in.get<std::size_t>() == computes.size(), "the number of computes differs");
    for (RegionCompute &c : computes)
      c.load(in);
    in.get(fragments_csv);
    in.get(last_fragments);
    in.get(last_fragments_time);
    in.get(fragments_found);
    in.get(step_offset);
  }
} // namespace perideal
