// Cells that turn into peridynamics during a run (adaptivity.h, doc/adaptivity.md).

#include <perideal/adaptivity/adaptivity.h>
#include <perideal/base/best_point.h>
#include <perideal/base/format.h>
#include <perideal/continuum/coupling.h>
#include <perideal/discretization/discretization.h>
#include <perideal/geometry/hexahedron.h>
#include <perideal/material/field_store.h>
#include <perideal/model/block.h>
#include <perideal/model/force_model.h>
#include <perideal/output/postprocess.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/rtree.h>

#include <algorithm>
#include <iomanip>
#include <limits>
#include <chrono>
#include <cmath>

namespace perideal
{
  using namespace dealii;
  namespace bgi = boost::geometry::index;

  /// The state that survives a conversion, by identity.
  struct Adaptivity::Snapshot
  {
    std::vector<PointKey>      keys;      // per old owned point
    std::vector<unsigned int>  order;     // old owned points sorted by key
    std::vector<std::uint8_t>  real;      // per old owned point: 1 if not a virtual or node point
    std::vector<double>        position;  // dim per old owned point
    std::vector<double>        alpha;     // per old owned point: its blending weight
    std::vector<unsigned int>  block;     // per old owned point
    std::vector<double>        u, v;      // dim per old owned point
    std::vector<std::size_t>   offsets;   // old bonds per old owned point (CSR)
    std::vector<unsigned int>  neighbor;  // per old bond, the far end as an index into far_keys; each family sorted by key
    std::vector<PointKey>      far_keys;  // the far ends' keys
    std::vector<std::size_t>   bond;      // the old bond index of each of them
    std::vector<std::uint8_t>  complete;  // per old owned point: 0 if its family lists only the bonds with a state; empty: all complete
    std::vector<std::uint8_t>  broken;    // per old bond (empty without damage)
    std::vector<double>        damage;    // per old bond (empty without continuous damage)
    // Per owned FE cell, sorted by CellId (a conversion may refine cells,
    // which renumbers them): its DoFs' u and v before the conversion, at
    // [cell_start[k], cell_start[k + 1]) of cell_u and cell_v (one array
    // for all cells, not one per cell), and its active FE index.
    std::vector<CellId>       cell_id;
    std::vector<std::size_t>  cell_start{0};
    std::vector<double>       cell_u, cell_v;
    std::vector<unsigned int> cell_fe;
    /// Appends a cell's values (in cell_id's order).
    void
    add_cell(const CellId &id, const unsigned int fe_index, const double *u, const double *v, const std::size_t n)
    {
      cell_id.push_back(id);
      cell_fe.push_back(fe_index);
      cell_u.insert(cell_u.end(), u, u + n);
      cell_v.insert(cell_v.end(), v, v + n);
      cell_start.push_back(cell_u.size());
    }
    std::size_t
    cell_dofs(const unsigned int k) const
    {
      return cell_start[k + 1] - cell_start[k];
    }
    FieldStore::History              history; // the models' history per old owned point and bond
  };
  namespace
  {
    /// The index in @p ids (sorted) of @p cell, or of its nearest ancestor
    /// (a conversion refined it), and that cell; invalid_unsigned_int if none.
    std::pair<unsigned int, Triangulation<dim>::cell_iterator>
    self_or_ancestor(const std::vector<CellId> &ids, Triangulation<dim>::cell_iterator cell)
    {
      for (;; cell = cell->parent())
        {
          const auto it = std::lower_bound(ids.begin(), ids.end(), cell->id());
          if (it != ids.end() && *it == cell->id())
            return {static_cast<unsigned int>(it - ids.begin()), cell};
          if (cell->level() == 0)
            return {numbers::invalid_unsigned_int, cell};
        }
    }
  } // namespace

  // ------------------------------------------------------------ parameters

  void
  AdaptivityParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Adaptivity");
    prm.declare_entry("Convertible blocks", "", Patterns::Anything(),
                      "Continuum blocks whose cells may turn into peridynamic cells during the run (comma "
                      "separated); empty: no conversion. Verlet, QuasiStatic and Newmark runs (doc/adaptivity.md).");
    prm.declare_entry("Peridynamic block", "", Patterns::Anything(),
                      "The peridynamic block whose material, damage model and horizon a converted cell takes. "
                      "Its Material must be the convertible blocks' own, so that a cell keeps its constants.");
    prm.declare_entry("Indicator", "maximum principal strain",
                      Patterns::Selection("maximum principal strain|strain energy density|damage"),
                      "What marks an FE cell for conversion, evaluated on the FE side before any PD damage "
                      "exists there. maximum principal strain: the largest eigenvalue of the cell's strain "
                      "at its centre, against Threshold times the critical stretch s_c of the Peridynamic "
                      "block's damage model. strain energy density: 1/2 eps:C:eps at the centre against "
                      "Threshold times E s_c^2 / 2 (the energy density of uniaxial stress at s_c). damage: "
                      "a PD point whose damage reaches Threshold marks every convertible cell within the "
                      "buffer of it.");
    prm.declare_entry("Threshold", "0.5", Patterns::Double(),
                      "The fraction of the indicator's critical value at which a cell converts (> 0).");
    prm.declare_entry("Check interval", "0", Patterns::Integer(0),
                      "Steps between two checks of the indicator. 0: every 10 steps of an explicit solver "
                      "(Verlet), after every accepted step of an implicit one (QuasiStatic, Newmark).");
    prm.declare_entry("Buffer width", "0", Patterns::Double(0),
                      "The convertible cells whose centres lie within this distance of a marked cell (or "
                      "damaged point) convert with it. 0: the rule horizon + blending band + the distance "
                      "the fastest wave of the convertible blocks travels in Check interval steps (none in "
                      "quasistatic load steps), so that no point whose bonds may break reaches an FE cell "
                      "before the next check. Given: at least the Peridynamic block's horizon.");
    prm.declare_entry("Check kept families", "false", Patterns::Bool(),
                      "After each conversion the points far from the changed ones keep their families "
                      "instead of a new neighbour search, the FE cells far from the converted ones their "
                      "coupling band, the points whose neighbours kept their families their stable step, and "
                      "the unchanged points their answers of the conditions' and computes' regions "
                      "(doc/adaptivity.md). true: search, compute and ask all of them again as well and stop "
                      "with an Error if a kept one differs (for testing; a conversion then costs about "
                      "twice).");
    prm.declare_entry("Buffer margin", "0", Patterns::Double(0),
                      "When a check finds a convertible cell within the buffer, the cells within the buffer "
                      "plus this distance convert with it: a crack that runs on finds its next cells "
                      "converted already, and conversions come fewer and larger (doc/adaptivity.md measures "
                      "it). 0: only the buffer.");
    prm.declare_entry("Refine converted cells", "false", Patterns::Bool(),
                      "true: a converted cell coarser than the finest cell of the Peridynamic block is refined "
                      "(p4est, one level per pass) until it is as fine, and each of its children becomes a PD "
                      "point: the FE cells can be coarse where nothing breaks and PD is fine where it does. FE "
                      "cells that p4est's 2:1 balance refines with them stay FE, their field interpolated; the "
                      "horizon is the block's. The refinement is part of a checkpoint (doc/adaptivity.md).");
    prm.declare_entry("Rebalance threshold", "0.25", Patterns::Double(0),
                      "At a conversion on several ranks: if the largest rank's work (its bonds, plus a few per "
                      "point and one per cell, the set-up's measure) would exceed the mean by more than this "
                      "fraction after it, the mesh is partitioned again by that work, predicted, before the "
                      "conversion's rebuild, and every point, bond and FE cell moves to its new rank with its "
                      "state; if the work is still out of balance after the conversion, it is partitioned again "
                      "(doc/adaptivity.md). 0: never (the partition of the set-up stays).");
    prm.leave_subsection();
  }

  void
  AdaptivityParameters::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Adaptivity");
    const std::string list = prm.get("Convertible blocks");
    convertible_names      = list.find_first_not_of(" \t,") == std::string::npos ?
                               std::vector<std::string>() :
                               split_names(list, "Adaptivity/Convertible blocks");
    pd_block_name          = Utilities::trim(prm.get("Peridynamic block"));
    const std::string kind = prm.get("Indicator");
    indicator      = kind == "damage"                 ? Indicator::damage :
                     kind == "strain energy density" ? Indicator::energy_density :
                                                        Indicator::principal_strain;
    threshold      = prm.get_double("Threshold");
    check_interval = prm.get_integer("Check interval");
    buffer         = prm.get_double("Buffer width");
    margin         = prm.get_double("Buffer margin");
    check_kept     = prm.get_bool("Check kept families");
    refine         = prm.get_bool("Refine converted cells");
    rebalance      = prm.get_double("Rebalance threshold");
    prm.leave_subsection();
  }

  void
  AdaptivityParameters::resolve(const std::vector<Block> &blocks)
  {
    if (!active())
      return;
    const auto find = [&](const std::string &name, const std::string &key) {
      std::string all;
      for (unsigned int b = 0; b < blocks.size(); ++b)
        {
          if (blocks[b].name == name)
            return b;
          all += (all.empty() ? "" : ", ") + blocks[b].name;
        }
      AssertThrow(false, ExcMessage(key + ": '" + name + "' is not a block of Blocks/Names (" + all + ")"));
      return 0u;
    };
    AssertThrow(!pd_block_name.empty(),
                ExcMessage("Adaptivity/Peridynamic block: empty, but Adaptivity/Convertible blocks is set: name "
                           "the peridynamic block whose material and damage model the converted cells take"));
    pd_block           = find(pd_block_name, "Adaptivity/Peridynamic block");
    const Block &target = blocks[pd_block];
    AssertThrow(!target.continuum && !target.rigid,
                ExcMessage("Adaptivity/Peridynamic block: block '" + target.name + "' is " +
                           (target.rigid ? "rigid" : "a continuum block") +
                           ": the converted cells need a peridynamic block to take its material"));
    AssertThrow(std::isfinite(threshold) && threshold > 0,
                ExcMessage("Adaptivity/Threshold must be a positive number, not " + sci(threshold)));
    AssertThrow(buffer == 0 || buffer >= target.horizon,
                ExcMessage("Adaptivity/Buffer width (" + sci(buffer) + ") is narrower than the horizon of block '" +
                           target.name + "' (" + sci(target.horizon) +
                           "): a point whose bonds break would reach an FE cell; give at least the horizon, "
                           "or 0 for the rule"));
    AssertThrow(indicator == Indicator::damage || (target.damage && target.damage->stretch_criterion()),
                ExcMessage("Adaptivity/Indicator: the strain and energy indicators compare with the critical "
                           "stretch of block '" + target.name + "'s damage model, and it has " +
                           (target.damage ? "'" + target.damage_name + "', which is not a critical stretch" :
                                            std::string("none")) +
                           ": use Indicator = damage, or give the block a critical stretch damage model"));
    convertible.clear();
    for (const auto &name : convertible_names)
      {
        const unsigned int b     = find(name, "Adaptivity/Convertible blocks");
        const Block       &block = blocks[b];
        AssertThrow(block.continuum,
                    ExcMessage("Adaptivity/Convertible blocks: block '" + name +
                               "' is not a continuum block: only FE cells convert"));
        AssertThrow(block.material_name == target.material_name,
                    ExcMessage("Adaptivity/Convertible blocks: block '" + name + "' has material '" +
                               block.material_name + "', the Peridynamic block '" + target.name + "' has '" +
                               target.material_name + "': its continuum model (linear elasticity of '" +
                               block.material_name + "') has no peridynamic counterpart in that block; a "
                               "converted cell keeps its material, so give both blocks the same Material"));
        convertible.push_back(b);
      }
  }

  // ------------------------------------------------------------ Adaptivity

  Adaptivity::Adaptivity(const AdaptivityParameters &parameters, Discretization &discretization, ForceModel &model,
                         Coupling &coupling, Postprocess &post, MechanicalState &state, RunRecord &record,
                         const MPI_Comm comm, ConditionalOStream &pcout, TimerOutput &timer,
                         std::function<void(double)> rebuild)
    : parameters(parameters)
    , discretization(discretization)
    , model(model)
    , coupling(coupling)
    , post(post)
    , state(state)
    , record(record)
    , comm(comm)
    , pcout(pcout)
    , timer(timer)
    , rebuild(std::move(rebuild))
  {
    const Block &target = discretization.blocks[parameters.pd_block];
    if (target.damage && target.damage->stretch_criterion())
      critical_stretch = target.damage->critical_stretch(0);
    for (const unsigned int b : parameters.convertible)
      {
        const Material &m = *discretization.blocks[b].material;
        wave_speed        = std::max(wave_speed, std::sqrt((m.bulk_modulus() + 4 * m.shear_modulus() / 3) / m.density()));
      }
    discretization.converted_block     = parameters.pd_block;
    discretization.check_kept_families = parameters.check_kept;
    if (parameters.refine)
      {
        // Converted cells are refined to the finest level of the PD block
        // (of the mesh if it starts without a cell).
        int finest = -1, deepest = 0;
        for (const auto &cell : discretization.dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              deepest = std::max(deepest, cell->level());
              if (discretization.block_of_cell(cell) == int(parameters.pd_block))
                finest = std::max(finest, cell->level());
            }
        finest       = Utilities::MPI::max(finest, comm);
        target_level = finest >= 0 ? finest : Utilities::MPI::max(deepest, comm);
      }
  }

  void
  Adaptivity::report_setup() const
  {
    std::string blocks;
    for (const auto &name : parameters.convertible_names)
      blocks += (blocks.empty() ? "" : ", ") + name;
    const char *what = parameters.indicator == AdaptivityParameters::Indicator::damage ? "point damage" :
                       parameters.indicator == AdaptivityParameters::Indicator::energy_density ?
                                                                                      "strain energy density / (E s_c^2 / 2)" :
                                                                                      "largest principal strain / s_c";
    pcout << "  adaptivity:        " << blocks << " -> " << parameters.pd_block_name << " where " << what
          << " >= " << parameters.threshold << ", checked "
          << (interval == 1 ? std::string("after every step") : "every " + std::to_string(interval) + " steps")
          << ", buffer " << sci(buffer_width(record.dt), 4)
          << (parameters.buffer > 0 ? " (given)" : inertia ? " (the rule, at this step)" : " (the rule)")
          << (parameters.margin > 0 ? ", margin " + sci(parameters.margin, 4) : std::string()) << "\n";
  }

  void
  Adaptivity::use_integrator(const bool explicit_steps, const bool with_inertia)
  {
    interval = parameters.check_interval > 0 ? parameters.check_interval : explicit_steps ? 10 : 1;
    inertia  = with_inertia;
  }

  double
  Adaptivity::buffer_width(const double dt) const
  {
    if (parameters.buffer > 0)
      return parameters.buffer;
    const double horizon = discretization.blocks[parameters.pd_block].horizon;
    return horizon * (1 + discretization.blending()) + (inertia ? wave_speed * interval * dt : 0.0);
  }

  double
  Adaptivity::cell_indicator(const CellIterator &cell, hp::FEValues<dim> &hp_values) const
  {
    // The strain at the cell's centre from its own FE field.
    const FiniteElement<dim> &fe = cell->get_fe();
    hp_values.reinit(cell);
    const FEValues<dim> &values = hp_values.get_present_fe_values();
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    cell->get_dof_indices(dofs);
    SymmetricTensor<2, dim> eps;
    for (unsigned int k = 0; k < dofs.size(); ++k)
      {
        const unsigned int     c = fe.system_to_component_index(k).first;
        const Tensor<1, dim>   g = values.shape_grad_component(k, 0, c) * coupling.continuum.U(dofs[k]);
        for (unsigned int d = 0; d < dim; ++d)
          eps[c][d] += (c == d ? 1.0 : 0.5) * g[d];
      }
    if (parameters.indicator == AdaptivityParameters::Indicator::principal_strain)
      return eigenvalues(eps)[0] / critical_stretch;
    const Material &m       = *discretization.blocks[discretization.block_of_cell(cell)].material;
    const double    K       = m.bulk_modulus(), G = m.shear_modulus();
    const double    lambda  = K - 2 * G / 3, E = 9 * K * G / (3 * K + G);
    const double    density = 0.5 * lambda * trace(eps) * trace(eps) + G * (eps * eps);
    return density / (0.5 * E * critical_stretch * critical_stretch);
  }

  std::vector<Point<dim>>
  Adaptivity::find_triggers() const
  {
    std::vector<Point<dim>> triggers;
    if (parameters.indicator == AdaptivityParameters::Indicator::damage)
      {
        for (unsigned int i = 0; i < discretization.cloud.n_owned(); ++i)
          if (!discretization.is_virtual(i) && !discretization.cloud.is_extra(i) &&
              model.point_damage(i) >= parameters.threshold)
            triggers.push_back(discretization.cloud.position(i));
        return triggers;
      }
    coupling.continuum.U.update_ghost_values();
    hp::QCollection<dim> centre;
    for (unsigned int k = 0; k < discretization.fe.size(); ++k)
      centre.push_back(QMidpoint<dim>());
    hp::FEValues<dim> values(discretization.fe, centre, update_gradients);
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && discretization.is_fe_cell(cell))
        {
          const int b = discretization.block_of_cell(cell);
          if (std::find(parameters.convertible.begin(), parameters.convertible.end(), b) !=
                parameters.convertible.end() &&
              cell_indicator(cell, values) >= parameters.threshold)
            triggers.push_back(cell->center());
        }
    return triggers;
  }

  std::size_t
  Adaptivity::mark_cells(const std::vector<Point<dim>> &triggers, const double width)
  {
    std::vector<std::uint8_t> &converted = discretization.converted;
    if (converted.empty())
      converted.assign(discretization.triangulation.n_active_cells(), 0);
    const auto              tree = pack_rtree(triggers);
    std::vector<Point<dim>> nearest; // reused: no allocation per cell
    // Owned and ghost cells alike, from the same triggers: every rank agrees
    // on the cells it shares.
    std::vector<std::pair<CellIterator, double>> candidates; // and their distances to the nearest trigger
    bool                                         needed = false;
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      if (!cell->is_artificial() && !converted[cell->active_cell_index()])
        {
          const int b = discretization.block_of_cell(cell);
          if (std::find(parameters.convertible.begin(), parameters.convertible.end(), b) ==
              parameters.convertible.end())
            continue;
          const Point<dim> x = cell->center();
          nearest.clear();
          tree.query(bgi::nearest(x, 1), std::back_inserter(nearest));
          const double distance = nearest.empty() ? std::numeric_limits<double>::max() : nearest[0].distance(x);
          if (distance <= width + parameters.margin)
            {
              candidates.emplace_back(cell, distance);
              needed |= distance <= width;
            }
        }
    // The margin converts with the buffer, never alone.
    if (Utilities::MPI::max(needed ? 1u : 0u, comm) == 0)
      return 0;
    std::size_t owned = 0;
    for (const auto &[cell, distance] : candidates)
      {
        converted[cell->active_cell_index()] = 1;
        owned += cell->is_locally_owned();
      }
    return owned;
  }

  unsigned int
  Adaptivity::refine_converted_cells()
  {
    TimerOutput::Scope t(timer, "adaptivity: refinement");
    unsigned int       made = 0;
    for (;;)
      {
        bool flagged = false;
        for (const auto &cell : discretization.dof_handler.active_cell_iterators())
          if (cell->is_locally_owned() && discretization.converted[cell->active_cell_index()] &&
              cell->level() < target_level)
            {
              cell->set_refine_flag();
              history.split.emplace_back(history.events.size(), cell->id().template to_binary<dim>());
              flagged = true;
            }
        if (Utilities::MPI::max(flagged ? 1u : 0u, comm) == 0)
          return made;
        execute_refinement();
        history.events.push_back(0);
        ++made;
      }
  }

  void
  Adaptivity::execute_refinement()
  {
    std::vector<std::uint8_t> &converted = discretization.converted;
    if (converted.empty()) // a restart's replay: the checkpoint has the flags
      {
        discretization.triangulation.execute_coarsening_and_refinement();
        return;
      }
    // The cells change their indices: the converted ones (owned and ghost)
    // and this rank's peridynamic ones by identity.
    std::vector<CellId> converted_ids, pd_ids;
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          const int b = discretization.block_of_cell(cell);
          if (converted[cell->active_cell_index()])
            converted_ids.push_back(cell->id());
          else if (cell->is_locally_owned() && b >= 0 && !discretization.blocks[b].continuum)
            pd_ids.push_back(cell->id());
        }
    std::sort(converted_ids.begin(), converted_ids.end());
    std::sort(pd_ids.begin(), pd_ids.end());
    discretization.triangulation.execute_coarsening_and_refinement();

    // A peridynamic cell that p4est's 2:1 balance split: its children's
    // points would have no state to come from.
    BestPoint          first(BestPoint::Order::smallest); // the split cell of the smallest x
    unsigned long long split = 0;
    for (const auto &cell : discretization.triangulation.active_cell_iterators())
      if (cell->is_locally_owned() && cell->level() > 0 &&
          std::binary_search(pd_ids.begin(), pd_ids.end(), cell->parent()->id()))
        {
          ++split;
          const Point<dim> x = cell->parent()->center();
          first.consider(x[0], 0, &x[0]);
        }
    split                 = Utilities::MPI::sum(split, comm);
    const BestPoint where = first.global(comm);
    std::string     at    = "(";
    for (unsigned int d = 0; d < dim; ++d)
      at += (d > 0 ? ", " : "") + sci(where.x[d]);
    at += ")";
    AssertThrow(split == 0,
                ExcMessage("Adaptivity/Refine converted cells: refining the converted cells to level " +
                           std::to_string(target_level) + " makes p4est's 2:1 balance split " +
                           std::to_string(split / GeometryInfo<dim>::max_children_per_cell) +
                           " peridynamic cells (one at " + at +
                           "), whose points would lose their state: give the peridynamic cells next to "
                           "convertible ones that level from the start (Discretization/Refinement regions)"));
    converted.assign(discretization.triangulation.n_active_cells(), 0);
    for (const auto &cell : discretization.triangulation.active_cell_iterators())
      if (!cell->is_artificial())
        converted[cell->active_cell_index()] =
          self_or_ancestor(converted_ids, cell).first != numbers::invalid_unsigned_int;
  }

  void
  Adaptivity::replay(const MeshHistory &events)
  {
    auto &triangulation = discretization.triangulation;
    const auto owned = [&](const PointKey &key) {
      const auto cell = triangulation.create_cell_iterator(CellId(key));
      AssertThrow(cell->is_active() && cell->is_locally_owned(),
                  ExcMessage("the checkpoint's mesh history does not match this mesh and partition"));
      return cell;
    };
    for (unsigned int e = 0; e < events.events.size(); ++e)
      {
        if (events.events[e] == 0)
          {
            for (const auto &[event, key] : events.split)
              if (event == e)
                owned(key)->set_refine_flag();
            execute_refinement();
          }
        else
          {
            for (const auto &cell : triangulation.active_cell_iterators())
              if (cell->is_locally_owned())
                cell->set_user_index(1);
            for (std::size_t k = 0; k < events.weighed.size(); ++k)
              if (events.weighed[k].first == e)
                owned(events.weighed[k].second)->set_user_index(events.weights[k]);
            discretization.repartition_by_cell_weights();
          }
      }
    history = events;
  }

  std::pair<double, double>
  Adaptivity::energies()
  {
    coupling.update_virtual_points(state.displacement);
    state.displacement.update_ghost_values();
    model.compute_forces(true);
    return post.energies();
  }

  bool
  Adaptivity::check(const unsigned int step, const double time, const double dt)
  {
    TimerOutput::Scope t(timer, "adaptivity");
    const auto         start = std::chrono::steady_clock::now();
    // 1. Where the indicator passes, on every rank.
    std::vector<Point<dim>> triggers;
    std::size_t             marked = 0;
    const double            width  = buffer_width(dt);
    {
      TimerOutput::Scope indicator(timer, "adaptivity: indicator");
      for (const auto &part : Utilities::MPI::all_gather(comm, find_triggers()))
        triggers.insert(triggers.end(), part.begin(), part.end());
      if (!triggers.empty())
        marked = Utilities::MPI::sum(mark_cells(triggers, width), comm);
    }
    if (marked == 0)
      {
        record.conversion_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return false;
      }
    TimerOutput::Scope conversion(timer, "adaptivity: conversion");
    // 2. The state before, by identity (moved to the ranks that own the
    // cells after the conversion if its work would be out of balance); the
    // converted cells refined; the new points, bonds and parts.
    const auto         before = energies();
    const PreviousCoupling band   = coupling_before_conversion(triggers, width);
    Moved              moved;
    const Snapshot     old    = snapshot_for_conversion(moved);
    const unsigned int splits = parameters.refine ? refine_converted_cells() : 0;
    // 3. The state after: carried over, the new points from the FE field.
    const PreviousFamilies keep = moved.moved ? moved.own.after_move(old, moved.reach) : PreviousFamilies();
    rebuild_and_restore(old, time, band, moved.moved ? &keep : nullptr);
    moved.own = OwnFamilies();
    const auto   after = energies();
    // Without inertia a velocity is no motion (QuasiStatic's Velocity = load
    // step): the strain energy alone, as in the balance.
    const double jump = (inertia ? after.first - before.first : 0.0) + after.second - before.second;
    record.conversion_energy += jump;
    ++record.conversions;
    record.converted_cells += marked;
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    record.conversion_seconds += took;
    const double bonds    = Utilities::MPI::sum(double(discretization.bonds.n_bonds()), comm);
    const double kept     = Utilities::MPI::sum(double(discretization.bonds.n_kept()), comm);
    const double owned    = Utilities::MPI::sum(double(discretization.cloud.n_owned()), comm);
    pcout << "Adaptivity: step " << step << ", t = " << sci(time, 6) << ": " << marked << " cells converted ("
          << triggers.size() << " marked by the indicator, buffer " << sci(width, 4) << ")"
          << (splits > 0 ? ", refined " + std::to_string(splits) + (splits == 1 ? " time" : " times") : std::string())
          << ", "
          << discretization.cloud.n_global() << " points, " << std::setprecision(12) << bonds
          << " bonds (" << std::setprecision(3) << 100 * kept / std::max(1.0, owned) << "% of the families kept, "
          << steps_carried() << "% of the stable steps); ";
    if (inertia)
      pcout << "kinetic " << sci(before.first, 6) << " -> " << sci(after.first, 6) << ", ";
    const double scale = (inertia ? std::abs(before.first) : 0.0) + std::abs(before.second);
    pcout << "strain " << sci(before.second, 6) << " -> " << sci(after.second, 6) << ": energy jump " << sci(jump, 3)
          << " (" << sci(jump / std::max(scale, std::numeric_limits<double>::min()), 3) << " relative); "
          << sci(took, 3) << " s" << std::endl;
    if (moved.moved)
      pcout << "Adaptivity: rebalanced with the conversion: its work would have been out of balance by "
            << sci(100 * moved.imbalance, 3) << "% (predicted), is by " << sci(100 * discretization.work_imbalance(), 3)
            << "%; the move took " << sci(moved.seconds, 3) << " s" << std::endl;
    if (parameters.rebalance > 0 && Utilities::MPI::n_mpi_processes(comm) > 1)
      rebalance(time);
    return true;
  }

  double
  Adaptivity::steps_carried() const
  {
    const auto [carried, computed] = model.carried_steps();
    return 100 * carried / std::max(1.0, carried + computed);
  }

  PreviousCoupling
  Adaptivity::coupling_before_conversion(std::vector<Point<dim>> triggers, const double width) const
  {
    // A converted cell's centre lies within the buffer and margin of a
    // trigger, and its points (after any refinement) within the cell.
    double largest = 0;
    for (const auto &cell : discretization.triangulation.active_cell_iterators())
      if (cell->is_locally_owned() && discretization.converted[cell->active_cell_index()])
        largest = std::max(largest, cell->diameter());
    PreviousCoupling band = discretization.record_coupling();
    band.centres          = std::move(triggers);
    band.radius           = width + parameters.margin + Utilities::MPI::max(largest, comm);
    return band;
  }

  Adaptivity::Snapshot
  Adaptivity::snapshot_for_conversion(Moved &moved)
  {
    if (parameters.rebalance <= 0 || Utilities::MPI::n_mpi_processes(comm) == 1)
      return take_snapshot();
    moved.imbalance = predict_work_imbalance();
    if (moved.imbalance <= parameters.rebalance)
      return take_snapshot();
    TimerOutput::Scope t(timer, "adaptivity: rebalance");
    const auto         start = std::chrono::steady_clock::now();
    Snapshot           now   = move_to_new_partition(take_snapshot(/*bonds_with_state_only=*/true));
    moved.own                = take_own_families();
    moved.reach              = discretization.cloud.max_cell_radius;
    moved.moved              = true;
    moved.seconds            = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return now;
  }

  double
  Adaptivity::predict_work_imbalance() const
  {
    // The work of the points there are (set_cell_weights()); a cell about
    // to convert (still FE) as the points it will hold; an FE cell the
    // coupling band will reach as the virtual points it will hold. Each
    // new point with the mean family of its kind now.
    discretization.set_cell_weights();
    const PointCloud &cloud = discretization.cloud;
    const Bonds      &bonds = discretization.bonds;
    double            sums[4] = {0, 0, 0, 0}; // bonds and points: of the peridynamic block, virtual
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      {
        const bool virtual_point = discretization.is_virtual(i);
        if (virtual_point || (cloud.block[i] == discretization.converted_block && !cloud.is_extra(i)))
          {
            sums[2 * virtual_point] += bonds.offsets[i + 1] - bonds.offsets[i];
            sums[2 * virtual_point + 1] += 1;
          }
      }
    Utilities::MPI::sum(sums, comm, sums);
    const double per_point   = (sums[1] > 0 ? sums[0] / sums[1] : 0.0) + 4;
    const double per_virtual = sums[3] > 0 ? sums[2] / sums[3] + 4 : per_point;
    const double most        = 4e9; // a cell's weight is an unsigned int

    // The converted cells without a PD point yet convert now (the earlier
    // converted ones keep their FE index: is_fe_cell()).
    const std::vector<std::uint8_t> &converted = discretization.converted;
    std::vector<std::uint8_t>        holds_point(discretization.triangulation.n_active_cells(), 0);
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (!discretization.is_virtual(i) && !cloud.is_extra(i))
        holds_point[cloud.cell[i]->active_cell_index()] = 1;
    std::vector<Point<dim>> converting; // the owned converting cells' centres, then every rank's
    double                  reach[2] = {0, -std::numeric_limits<double>::max()}; // largest diameter, -smallest point volume
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && converted[cell->active_cell_index()] && cell->active_fe_index() > 0 &&
          !holds_point[cell->active_cell_index()])
        {
          const int    levels = parameters.refine ? std::max(0, target_level - cell->level()) : 0;
          const double points = std::pow(double(GeometryInfo<dim>::max_children_per_cell), levels);
          cell->set_user_index(static_cast<unsigned int>(std::min(points * per_point, most)));
          converting.push_back(cell->center());
          reach[0] = std::max(reach[0], cell->diameter());
          reach[1] = std::max(reach[1], -cell_volume(cell) / points);
        }
    Utilities::MPI::max(reach, comm, reach);
    std::vector<Point<dim>> all;
    for (const auto &part : Utilities::MPI::all_gather(comm, converting))
      all.insert(all.end(), part.begin(), part.end());
    // The band's rule (Discretization::build_coupled_cloud()), the
    // converting cells' centres for their points.
    const double serves =
      discretization.virtual_point_reach(discretization.blocks[discretization.converted_block].horizon);
    const auto tree = pack_rtree(all);
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && discretization.is_fe_cell(cell) && !converted[cell->active_cell_index()] &&
          !discretization.cell_virtual[cell->active_cell_index()])
        for (const auto &x : tree | bgi::adaptors::queried(bgi::nearest(cell->center(), 1)))
          if (x.distance(cell->center()) - 0.5 * (cell->diameter() + reach[0]) <= serves)
            {
              const int    levels = discretization.virtual_levels(cell_volume(cell), -reach[1]);
              const double points = std::pow(double(GeometryInfo<dim>::max_children_per_cell), levels);
              cell->set_user_index(static_cast<unsigned int>(std::min(cell->user_index() + points * per_virtual, most)));
            }

    double work = 0;
    for (const auto &cell : discretization.triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        work += cell->user_index();
    const auto balance = Utilities::MPI::min_max_avg(work, comm);
    return balance.avg > 0 ? balance.max / balance.avg - 1 : 0.0;
  }

  // ------------------------------------------------------------ rebalance

  namespace
  {
    /// Plain values into and out of a cell's bytes (a rebalance's transfer).
    template <typename T>
    void
    put(std::vector<char> &bytes, const T &value)
    {
      static_assert(std::is_trivially_copyable_v<T>, "plain values only");
      const char *p = reinterpret_cast<const char *>(&value);
      bytes.insert(bytes.end(), p, p + sizeof(T));
    }
    template <typename T>
    void
    put(std::vector<char> &bytes, const T *values, const std::size_t n)
    {
      const char *p = reinterpret_cast<const char *>(values);
      bytes.insert(bytes.end(), p, p + n * sizeof(T));
    }
    struct Reader
    {
      std::vector<char>::const_iterator at;
      template <typename T>
      T
      get()
      {
        T value;
        std::copy(at, at + sizeof(T), reinterpret_cast<char *>(&value));
        at += sizeof(T);
        return value;
      }
      template <typename T>
      void
      get(std::vector<T> &to, const std::size_t n)
      {
        const std::size_t first = to.size();
        to.resize(first + n);
        std::copy(at, at + n * sizeof(T), reinterpret_cast<char *>(to.data() + first));
        at += n * sizeof(T);
      }
    };
  } // namespace

  void
  Adaptivity::rebalance(const double time)
  {
    const double imbalance = discretization.work_imbalance();
    if (imbalance <= parameters.rebalance)
      return;
    TimerOutput::Scope t(timer, "adaptivity: rebalance");
    const auto         start = std::chrono::steady_clock::now();
    discretization.set_cell_weights();
    const PreviousCoupling band  = discretization.record_coupling(); // no point appears: every cell that stays keeps it
    Snapshot               moved = move_to_new_partition(take_snapshot(/*bonds_with_state_only=*/true));
    // The points that stay on this rank keep their families (no point moved
    // in space); only those of the points that arrive are searched.
    const OwnFamilies      own  = take_own_families();
    const PreviousFamilies keep = own.to_keep(discretization.cloud.max_cell_radius);

    // The points, bonds and parts of the new partition, the state from what moved.
    rebuild_and_restore(moved, time, band, &keep);
    energies(); // the forces of the new numbering
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    record.conversion_seconds += took;
    const double kept  = Utilities::MPI::sum(double(discretization.bonds.n_kept()), comm);
    const double owned = Utilities::MPI::sum(double(discretization.cloud.n_owned()), comm);
    pcout << "Adaptivity: rebalanced, the work out of balance by " << sci(100 * imbalance, 3) << "% -> "
          << sci(100 * discretization.work_imbalance(), 3) << "% (" << std::setprecision(3)
          << 100 * kept / std::max(1.0, owned) << "% of the families kept, " << steps_carried()
          << "% of the stable steps); " << sci(took, 3) << " s" << std::endl;
  }

  Adaptivity::Snapshot
  Adaptivity::move_to_new_partition(Snapshot old)
  {
    // Each owned cell's share of the state packed for the rank that owns
    // the cell after p4est partitioned the mesh by the cells' weights.
    Snapshot                               moved;
    moved.history.point_width = old.history.point_width;
    moved.history.bond_width  = old.history.bond_width;
    moved.offsets.push_back(0);
    std::vector<std::vector<unsigned int>> in_cell(discretization.triangulation.n_active_cells());
    for (unsigned int i = 0; i < discretization.cloud.n_owned(); ++i)
      in_cell[discretization.cloud.cell[i]->active_cell_index()].push_back(i);
    std::vector<std::uint8_t> &converted = discretization.converted;
    auto &triangulation = discretization.triangulation;
    const unsigned int handle = triangulation.register_data_attach(
      [&](const Triangulation<dim>::cell_iterator &cell, const Triangulation<dim>::CellStatus) {
        return pack_cell(old, in_cell[cell->active_cell_index()], cell,
                         !converted.empty() && converted[cell->active_cell_index()]);
      },
      /*returns_variable_size_data=*/true);
    // The weights go into the mesh history (a restart partitions by them).
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          history.weighed.emplace_back(history.events.size(), cell->id().template to_binary<dim>());
          history.weights.push_back(cell->user_index());
        }
    history.events.push_back(1);
    discretization.repartition_by_cell_weights();
    // Packed and sent: the sender's copy is not needed while the moved one is built.
    old     = Snapshot();
    in_cell = std::vector<std::vector<unsigned int>>();
    std::vector<CellId> converted_ids;
    triangulation.notify_ready_to_unpack(handle,
                                         [&](const Triangulation<dim>::cell_iterator &cell,
                                             const Triangulation<dim>::CellStatus,
                                             const boost::iterator_range<std::vector<char>::const_iterator> &data) {
                                           if (unpack_cell(moved, cell, data))
                                             converted_ids.push_back(cell->id());
                                         });
    finish_moved(moved);
    set_converted_after_rebalance(converted_ids);
    add_ghost_fe_cells(moved);
    return moved;
  }

  std::vector<char>
  Adaptivity::pack_cell(const Snapshot &old, const std::vector<unsigned int> &points,
                        const Triangulation<dim>::cell_iterator &cell, const bool converted) const
  {
    std::vector<char> bytes;
    put(bytes, std::uint8_t(converted));
    put(bytes, std::uint32_t(points.size()));
    for (const unsigned int i : points)
      {
        put(bytes, old.keys[i]);
        put(bytes, old.real[i]);
        put(bytes, &old.position[dim * i], dim);
        put(bytes, old.alpha[i]);
        put(bytes, old.block[i]);
        put(bytes, &old.u[dim * i], dim);
        put(bytes, &old.v[dim * i], dim);
        put(bytes, &old.history.points[std::size_t(old.history.point_width) * i], old.history.point_width);
        put(bytes, std::uint64_t(old.offsets[i + 1] - old.offsets[i]));
        for (std::size_t k = old.offsets[i]; k < old.offsets[i + 1]; ++k)
          {
            const std::size_t b = old.bond[k];
            put(bytes, old.far_keys[old.neighbor[k]]);
            if (!old.broken.empty())
              put(bytes, old.broken[b]);
            if (!old.damage.empty())
              put(bytes, old.damage[b]);
            put(bytes, &old.history.bonds[std::size_t(old.history.bond_width) * b], old.history.bond_width);
          }
      }
    // The FE cell's values, if it is one (nothing was refined since the snapshot).
    const unsigned int k  = self_or_ancestor(old.cell_id, cell).first;
    const bool         fe = k != numbers::invalid_unsigned_int;
    put(bytes, std::uint8_t(fe));
    if (fe)
      {
        put(bytes, std::uint32_t(old.cell_fe[k]));
        put(bytes, std::uint32_t(old.cell_dofs(k)));
        put(bytes, &old.cell_u[old.cell_start[k]], old.cell_dofs(k));
        put(bytes, &old.cell_v[old.cell_start[k]], old.cell_dofs(k));
      }
    return bytes;
  }

  bool
  Adaptivity::unpack_cell(Snapshot &moved, const Triangulation<dim>::cell_iterator &cell,
                          const boost::iterator_range<std::vector<char>::const_iterator> &data) const
  {
    Reader             in{data.begin()};
    const bool         converted = in.get<std::uint8_t>();
    const unsigned int n         = in.get<std::uint32_t>();
    for (unsigned int p = 0; p < n; ++p)
      {
        moved.keys.push_back(in.get<PointKey>());
        moved.real.push_back(in.get<std::uint8_t>());
        in.get(moved.position, dim);
        moved.alpha.push_back(in.get<double>());
        moved.block.push_back(in.get<unsigned int>());
        in.get(moved.u, dim);
        in.get(moved.v, dim);
        in.get(moved.history.points, moved.history.point_width);
        const std::size_t family = in.get<std::uint64_t>();
        for (std::size_t k = 0; k < family; ++k)
          {
            moved.bond.push_back(moved.neighbor.size());
            moved.neighbor.push_back(moved.far_keys.size());
            moved.far_keys.push_back(in.get<PointKey>());
            if (!model.broken.empty())
              moved.broken.push_back(in.get<std::uint8_t>());
            if (!model.damage.empty())
              moved.damage.push_back(in.get<double>());
            in.get(moved.history.bonds, moved.history.bond_width);
          }
        moved.offsets.push_back(moved.neighbor.size());
      }
    if (in.get<std::uint8_t>())
      {
        moved.cell_id.push_back(cell->id());
        moved.cell_fe.push_back(in.get<std::uint32_t>());
        const unsigned int dofs = in.get<std::uint32_t>();
        in.get(moved.cell_u, dofs);
        in.get(moved.cell_v, dofs);
        moved.cell_start.push_back(moved.cell_u.size());
      }
    AssertThrow(in.at == data.end(), ExcInternalError());
    return converted;
  }

  void
  Adaptivity::finish_moved(Snapshot &moved) const
  {
    moved.complete.assign(moved.keys.size(), 0); // packed with the bonds with a state only
    moved.order.resize(moved.keys.size());
    for (unsigned int i = 0; i < moved.order.size(); ++i)
      moved.order[i] = i;
    std::sort(moved.order.begin(), moved.order.end(),
              [&](const unsigned int a, const unsigned int b) { return moved.keys[a] < moved.keys[b]; });
    // The FE cells in CellId order.
    std::vector<unsigned int> by_id(moved.cell_id.size());
    for (unsigned int k = 0; k < by_id.size(); ++k)
      by_id[k] = k;
    std::sort(by_id.begin(), by_id.end(),
              [&](const unsigned int a, const unsigned int b) { return moved.cell_id[a] < moved.cell_id[b]; });
    Snapshot sorted;
    sorted.cell_u.reserve(moved.cell_u.size());
    sorted.cell_v.reserve(moved.cell_v.size());
    for (const unsigned int k : by_id)
      sorted.add_cell(moved.cell_id[k], moved.cell_fe[k], &moved.cell_u[moved.cell_start[k]],
                      &moved.cell_v[moved.cell_start[k]], moved.cell_dofs(k));
    moved.cell_id    = std::move(sorted.cell_id);
    moved.cell_fe    = std::move(sorted.cell_fe);
    moved.cell_start = std::move(sorted.cell_start);
    moved.cell_u     = std::move(sorted.cell_u);
    moved.cell_v     = std::move(sorted.cell_v);
  }

  void
  Adaptivity::set_converted_after_rebalance(std::vector<CellId> &owned_converted)
  {
    // The owned cells' flags came with them; the ghosts' from their owners.
    std::sort(owned_converted.begin(), owned_converted.end());
    std::vector<std::uint8_t> &converted = discretization.converted;
    converted.assign(discretization.triangulation.n_active_cells(), 0);
    for (const auto &cell : discretization.triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        converted[cell->active_cell_index()] =
          std::binary_search(owned_converted.begin(), owned_converted.end(), cell->id());
    GridTools::exchange_cell_data_to_ghosts<std::uint8_t, Triangulation<dim>>(
      discretization.triangulation,
      [&](const Triangulation<dim>::active_cell_iterator &cell) { return converted[cell->active_cell_index()]; },
      [&](const Triangulation<dim>::active_cell_iterator &cell, const std::uint8_t flag) {
        converted[cell->active_cell_index()] = flag;
      });
  }

  void
  Adaptivity::add_ghost_fe_cells(Snapshot &moved) const
  {
    // Per FE cell: its active FE index, then u and v.
    std::vector<std::pair<CellId, std::vector<double>>> ghosts;
    GridTools::exchange_cell_data_to_ghosts<std::vector<double>, Triangulation<dim>>(
      discretization.triangulation,
      [&](const Triangulation<dim>::active_cell_iterator &cell) -> std_cxx17::optional<std::vector<double>> {
        const auto it = std::lower_bound(moved.cell_id.begin(), moved.cell_id.end(), cell->id());
        if (it == moved.cell_id.end() || *it != cell->id())
          return {};
        const std::size_t   k = it - moved.cell_id.begin();
        std::vector<double> data(1, moved.cell_fe[k]);
        data.insert(data.end(), moved.cell_u.begin() + moved.cell_start[k], moved.cell_u.begin() + moved.cell_start[k + 1]);
        data.insert(data.end(), moved.cell_v.begin() + moved.cell_start[k], moved.cell_v.begin() + moved.cell_start[k + 1]);
        return data;
      },
      [&](const Triangulation<dim>::active_cell_iterator &cell, const std::vector<double> &data) {
        ghosts.emplace_back(cell->id(), data);
      });
    for (auto &[id, data] : ghosts)
      {
        const std::size_t n = (data.size() - 1) / 2;
        moved.add_cell(id, static_cast<unsigned int>(data[0]), &data[1], &data[1 + n], n);
      }
    finish_moved(moved); // CellId order again
  }

  Adaptivity::OwnFamilies
  Adaptivity::take_own_families()
  {
    OwnFamilies own;
    Bonds &bonds = discretization.bonds;
    own.keys     = discretization.cloud.key; // owned, then ghosts: the far ends' keys
    own.offsets  = std::move(bonds.offsets); // the rebuild replaces them
    own.neighbor = std::move(bonds.neighbor);
    own.order.resize(own.offsets.empty() ? 0 : own.offsets.size() - 1);
    for (unsigned int i = 0; i < own.order.size(); ++i)
      own.order[i] = i;
    std::sort(own.order.begin(), own.order.end(),
              [&](const unsigned int a, const unsigned int b) { return own.keys[a] < own.keys[b]; });
    return own;
  }

  PreviousFamilies
  Adaptivity::OwnFamilies::to_keep(const double extra_reach) const
  {
    PreviousFamilies families;
    families.keys           = &keys;
    families.order          = &order;
    families.offsets        = &offsets;
    families.neighbor_index = &neighbor;
    families.index_keys     = &keys;
    families.extra_reach    = extra_reach;
    families.nothing_moved  = true;
    return families;
  }

  PreviousFamilies
  Adaptivity::OwnFamilies::after_move(const Snapshot &moved, const double extra_reach) const
  {
    // The families of the points that stayed, as in a rebalance; where the
    // conversion changed points is found against every point this rank owns
    // now, as it was before (the moved snapshot), not against the points it
    // owned: one that arrived from another rank did not change.
    PreviousFamilies families = to_keep(extra_reach);
    families.nothing_moved    = false;
    families.compared_keys    = &moved.keys;
    families.compared_order   = &moved.order;
    families.positions        = &moved.position;
    families.alpha            = &moved.alpha;
    families.block            = &moved.block;
    return families;
  }

  void
  Adaptivity::rebuild_and_restore(const Snapshot &old, const double time, const PreviousCoupling &band,
                                  const PreviousFamilies *keep)
  {
    const PreviousFamilies families  = keep != nullptr ? *keep : families_to_keep(old);
    discretization.previous_families = &families;
    discretization.previous_coupling = &band;
    try
      {
        rebuild(time);
      }
    catch (...)
      {
        discretization.previous_families = nullptr;
        discretization.previous_coupling = nullptr;
        throw;
      }
    discretization.previous_families = nullptr;
    discretization.previous_coupling = nullptr;
    restore(old);
  }

  PreviousFamilies
  Adaptivity::families_to_keep(const Snapshot &old) const
  {
    PreviousFamilies families;
    families.keys        = &old.keys;
    families.order       = &old.order;
    families.offsets     = &old.offsets;
    families.neighbor_index = &old.neighbor;
    families.index_keys     = &old.far_keys;
    families.positions   = &old.position;
    families.alpha       = &old.alpha;
    families.block       = &old.block;
    families.complete    = old.complete.empty() ? nullptr : &old.complete;
    families.extra_reach = discretization.cloud.max_cell_radius;
    return families;
  }

  void
  Adaptivity::restore_converted(const std::vector<std::uint8_t> &converted)
  {
    const bool any = std::any_of(converted.begin(), converted.end(), [](const std::uint8_t c) { return c != 0; });
    if (Utilities::MPI::max(any ? 1u : 0u, comm) == 0)
      return;
    discretization.converted = converted;
    // The loads are evaluated again for the checkpoint's time by the
    // integrator; the record (conversions, jumps) comes with the state.
    rebuild(0.0);
  }

  // ------------------------------------------------------------ state transfer




  Adaptivity::Snapshot
  Adaptivity::take_snapshot(const bool bonds_with_state_only) const
  {
    const PointCloud &cloud = discretization.cloud;
    const Bonds      &bonds = discretization.bonds;
    Snapshot          old;
    const unsigned int n = cloud.n_owned();
    old.keys.assign(cloud.key.begin(), cloud.key.begin() + n);
    old.order.resize(n);
    for (unsigned int i = 0; i < n; ++i)
      old.order[i] = i;
    std::sort(old.order.begin(), old.order.end(), [&](const unsigned int a, const unsigned int b) {
      return old.keys[a] < old.keys[b];
    });
    old.real.resize(n);
    for (unsigned int i = 0; i < n; ++i)
      old.real[i] = !discretization.is_virtual(i) && !cloud.is_extra(i);
    old.position.assign(cloud.X.begin(), cloud.X.begin() + dim * n);
    old.alpha.assign(discretization.point_alpha.begin(), discretization.point_alpha.begin() + n);
    old.block.assign(cloud.block.begin(), cloud.block.begin() + n);
    old.u.assign(state.displacement.begin(), state.displacement.begin() + dim * n);
    old.v.assign(state.velocity.begin(), state.velocity.begin() + dim * n);
    old.broken  = model.broken;
    old.damage  = model.damage;
    old.history = model.field_store().history(n, bonds.n_bonds());
    // Each family sorted by the far end's key: a bond is found again by it
    // (find_families() sorts them so; checked, not assumed). Only its bonds
    // with a state (a rebalance): the others are found again by the search
    // and start intact, as they were.
    const std::size_t width     = old.history.bond_width;
    const auto        has_state = [&](const std::size_t b) {
      if ((!old.broken.empty() && old.broken[b] != 0) || (!old.damage.empty() && old.damage[b] != 0))
        return true;
      for (std::size_t q = 0; q < width; ++q)
        if (old.history.bonds[width * b + q] != 0)
          return true;
      return false;
    };
    old.offsets.assign(1, 0);
    if (!bonds_with_state_only)
      {
        old.neighbor.reserve(bonds.n_bonds());
        old.bond.reserve(bonds.n_bonds());
      }
    old.far_keys = cloud.key;
    const auto by_far_key = [&](const std::size_t a, const std::size_t b) {
      return cloud.key[bonds.neighbor[a]] < cloud.key[bonds.neighbor[b]];
    };
    std::vector<std::size_t> family;
    for (unsigned int i = 0; i < n; ++i)
      {
        family.clear();
        for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
          if (!bonds_with_state_only || has_state(b))
            family.push_back(b);
        if (!std::is_sorted(family.begin(), family.end(), by_far_key))
          std::sort(family.begin(), family.end(), by_far_key);
        for (const std::size_t b : family)
          {
            old.neighbor.push_back(bonds.neighbor[b]);
            old.bond.push_back(b);
          }
        old.offsets.push_back(old.neighbor.size());
      }
    if (bonds_with_state_only)
      old.complete.assign(n, 0);
    // The FE field cell by cell, with the element it had, in CellId order;
    // the ghost cells too: an owned DoF may lie on ghost FE cells only
    // (beside an owned PD cell), and restore_fe_field() reads them. The
    // hanging DoFs from their masters first: the time loop keeps U's so,
    // not V's (they carry no mass), and a cell's values are copied or
    // interpolated below.
    state.distribute_displacement();
    state.distribute_velocity();
    ContinuumField &fe = coupling.continuum;
    fe.U.update_ghost_values();
    fe.V.update_ghost_values();
    std::vector<std::pair<CellId, CellIterator>> cells;
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      if (!cell->is_artificial() && discretization.was_fe_cell(cell))
        cells.emplace_back(cell->id(), cell);
    std::sort(cells.begin(), cells.end(), [](const auto &a, const auto &b) { return a.first < b.first; });
    std::vector<types::global_dof_index> dofs;
    std::vector<double>                  u, v;
    for (const auto &[id, cell] : cells)
      {
        dofs.resize(cell->get_fe().n_dofs_per_cell());
        cell->get_dof_indices(dofs);
        u.resize(dofs.size());
        v.resize(dofs.size());
        for (unsigned int j = 0; j < dofs.size(); ++j)
          u[j] = fe.U(dofs[j]), v[j] = fe.V(dofs[j]);
        old.add_cell(id, cell->active_fe_index(), u.data(), v.data(), dofs.size());
      }
    fe.V.zero_out_ghost_values();
    return old;
  }

  unsigned int
  Adaptivity::old_point(const Snapshot &old, const PointKey &key) const
  {
    return find_by_key(old.keys, old.order, key);
  }

  std::pair<unsigned int, Triangulation<dim>::cell_iterator>
  Adaptivity::old_fe_cell(const Snapshot &old, const CellIterator &cell) const
  {
    return self_or_ancestor(old.cell_id, cell);
  }

  std::array<double, 2 * dim>
  Adaptivity::interpolate(const Snapshot &old, const unsigned int k, const Triangulation<dim>::cell_iterator &source,
                          const Point<dim> &x, const Mapping<dim> &mapping) const
  {
    const FiniteElement<dim> &fe   = discretization.fe[old.cell_fe[k]];
    const Point<dim>          unit = mapping.transform_real_to_unit_cell(source, x);
    std::array<double, 2 * dim> uv{};
    for (unsigned int j = 0; j < fe.n_dofs_per_cell(); ++j)
      {
        const unsigned int d   = fe.system_to_component_index(j).first;
        const double       phi = fe.shape_value_component(j, unit, d);
        uv[d] += phi * old.cell_u[old.cell_start[k] + j];
        uv[dim + d] += phi * old.cell_v[old.cell_start[k] + j];
      }
    return uv;
  }

  void
  Adaptivity::restore_fe_field(const Snapshot &old, const Mapping<dim> &mapping)
  {
    // The cells that stay FE from their own values; those a conversion
    // refined around the converted ones (p4est's 2:1 balance) from their
    // parent's field at their support points, which the nested Lagrange
    // elements reproduce exactly. Every owned DoF, also one that lies on
    // ghost FE cells only (beside an owned PD cell: the DoF is this rank's).
    // A DoF on several cells takes the value of the one of smallest CellId
    // (the cells visited in decreasing order, the last write wins):
    // interpolated values differ in round-off from cell to cell, and this
    // choice does not depend on the partition.
    ContinuumField                              &fe = coupling.continuum;
    std::vector<std::pair<CellId, CellIterator>> cells;
    for (const auto &cell : discretization.dof_handler.active_cell_iterators())
      if (!cell->is_artificial() && discretization.is_fe_cell(cell))
        cells.emplace_back(cell->id(), cell);
    std::sort(cells.begin(), cells.end(), [](const auto &a, const auto &b) { return b.first < a.first; });
    std::vector<types::global_dof_index> dofs;
    for (const auto &[id, cell] : cells)
      {
        const auto [k, source] = old_fe_cell(old, cell);
        if (k == numbers::invalid_unsigned_int && !cell->is_locally_owned())
          continue; // a ghost cell new to this rank: its owned DoFs lie on owned cells too
        AssertThrow(k != numbers::invalid_unsigned_int && old.cell_fe[k] == cell->active_fe_index(),
                    ExcInternalError());
        const FiniteElement<dim> &element = cell->get_fe();
        dofs.resize(element.n_dofs_per_cell());
        cell->get_dof_indices(dofs);
        const bool same = source->level() == cell->level();
        for (unsigned int j = 0; j < dofs.size(); ++j)
          if (fe.U.in_local_range(dofs[j]))
            {
              if (same)
                {
                  fe.U(dofs[j]) = old.cell_u[old.cell_start[k] + j];
                  fe.V(dofs[j]) = old.cell_v[old.cell_start[k] + j];
                  continue;
                }
              const Point<dim> x =
                mapping.transform_unit_to_real_cell(cell, element.get_unit_support_points()[j]);
              const auto         uv = interpolate(old, k, source, x, mapping);
              const unsigned int d  = element.system_to_component_index(j).first;
              fe.U(dofs[j])         = uv[d];
              fe.V(dofs[j])         = uv[dim + d];
            }
      }
  }


  void
  Adaptivity::restore(const Snapshot &old)
  {
    const PointCloud  &cloud = discretization.cloud;
    const unsigned int n     = cloud.n_owned();
    std::vector<unsigned int> point_map(n, numbers::invalid_unsigned_int);
    const MappingQ1<dim>      mapping;
    for (unsigned int i = 0; i < n; ++i)
      {
        point_map[i] = old_point(old, cloud.key[i]);
        if (discretization.is_virtual(i) || cloud.is_extra(i))
          continue; // they follow the FE field
        // (A level-0 virtual point had the key of its cell's new point:
        // its u and v are the FE field's, taken below as for the others.)
        if (point_map[i] != numbers::invalid_unsigned_int && old.real[point_map[i]])
          for (unsigned int d = 0; d < dim; ++d)
            {
              state.displacement.local_element(dim * i + d) = old.u[dim * point_map[i] + d];
              state.velocity.local_element(dim * i + d)     = old.v[dim * point_map[i] + d];
            }
        else
          {
            // A converted cell's point: the FE field at its centroid, of its
            // own cell or, if the conversion refined it, of the cell it came from.
            const auto [k, source] = old_fe_cell(old, cloud.cell[i]);
            AssertThrow(k != numbers::invalid_unsigned_int, ExcInternalError());
            std::array<double, 2 * dim> uv = interpolate(old, k, source, cloud.position(i), mapping);
            for (unsigned int d = 0; d < dim; ++d)
              {
                state.displacement.local_element(dim * i + d) = uv[d];
                state.velocity.local_element(dim * i + d)     = uv[dim + d];
              }
          }
      }
    restore_fe_field(old, mapping);
    state.distribute_displacement();
    state.distribute_velocity();
    restore_bonds(old, point_map);
  }

  void
  Adaptivity::restore_bonds(const Snapshot &old, const std::vector<unsigned int> &point_map)
  {
    const PointCloud &cloud = discretization.cloud;
    const Bonds      &bonds = discretization.bonds;
    std::vector<std::size_t> bond_map(bonds.n_bonds(), std::size_t(-1));
    // The bonds that existed keep their damage; new ones start intact (or
    // as the initial damage makes them).
    for (unsigned int i = 0; i < point_map.size(); ++i)
      if (point_map[i] != numbers::invalid_unsigned_int)
        {
          const unsigned int o     = point_map[i];
          const auto         first = old.neighbor.begin() + old.offsets[o], last = old.neighbor.begin() + old.offsets[o + 1];
          // A kept family comes in the snapshot's order: bond by bond, no search.
          std::size_t b = bonds.offsets[i];
          if (bonds.offsets[i + 1] - b == std::size_t(last - first))
            for (auto it = first; it != last && cloud.key[bonds.neighbor[b]] == old.far_keys[*it]; ++it, ++b)
              bond_map[b] = old.bond[it - old.neighbor.begin()];
          for (; b < bonds.offsets[i + 1]; ++b)
            {
              const PointKey &key = cloud.key[bonds.neighbor[b]];
              const auto      it  = std::lower_bound(first, last, key, [&](const unsigned int k, const PointKey &x) {
                return old.far_keys[k] < x;
              });
              if (it != last && old.far_keys[*it] == key)
                bond_map[b] = old.bond[it - old.neighbor.begin()];
            }
        }
    for (std::size_t b = 0; b < bond_map.size(); ++b)
      if (bond_map[b] != std::size_t(-1))
        {
          if (!model.broken.empty() && !old.broken.empty())
            model.broken[b] = old.broken[bond_map[b]];
          if (!model.damage.empty() && !old.damage.empty())
            model.damage[b] = old.damage[bond_map[b]];
        }
    model.field_store().carry_history(old.history, point_map, bond_map);
  }
} // namespace perideal
