// The mesh, DoFs, point cloud and bonds (discretization.h).

#include <perideal/base/best_point.h>
#include <perideal/base/expression.h>
#include <perideal/base/format.h>
#include <perideal/discretization/discretization.h>
#include <perideal/discretization/size_estimate.h>
#include <perideal/geometry/hexahedron.h>
#include <perideal/neighborhood/partial_volumes.h>
#include <perideal/simulation/deck.h>

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/mpi.templates.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_dgq.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/numerics/rtree.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <sstream>

namespace perideal
{
  using namespace dealii;
  namespace bgi = boost::geometry::index;

  Discretization::Discretization(Deck &deck, const MPI_Comm comm, ConditionalOStream &pcout, TimerOutput &timer,
                                 const bool dry_run_mode)
    : scene(deck.scene)
    , regions(deck.regions)
    , bond_filters(deck.bond_filters)
    , initial_damage(deck.initial_damage)
    , blocks(deck.blocks)
    , contact(deck.contact)
    , has_continuum(deck.has_continuum)
    , force_blending(deck.has_continuum && deck.coupling.scheme == CouplingParameters::Scheme::force)
    , conversions_refine(deck.adaptivity.active() && deck.adaptivity.refine)
    // Conversions that refine cells keep the partition (the state moves by
    // identity on each rank): p4est repartitions only when asked to.
    , triangulation(comm, Triangulation<dim>::none,
                    conversions_refine ? parallel::distributed::Triangulation<dim>::no_automatic_repartitioning :
                                         parallel::distributed::Triangulation<dim>::default_setting)
    , fe(FESystem<dim>(FE_DGQ<dim>(0), dim), FESystem<dim>(FE_Q<dim>(1), dim), FESystem<dim>(FE_Q<dim>(2), dim))
    , dof_handler(triangulation)
    , comm(comm)
    , pcout(pcout)
    , timer(timer)
    , blending_width(deck.coupling.blending_width)
    , virtual_point_levels(deck.coupling.virtual_point_levels)
    , dry_run_mode(dry_run_mode)
  {
    geometry_connections = on_mesh_change(triangulation, [this]() {
      cell_geometry.clear();
      dofs_numbered = false;
      converted_when_built.clear(); // by the old cells' indices
    });
  }

  std::vector<unsigned int>
  Discretization::points_in_region(const std::string &region, const std::vector<unsigned int> &before) const
  {
    // (previous_point is current only inside the rebuild that made it.)
    const bool                carry = previous_families != nullptr && !previous_point.empty();
    std::vector<std::uint8_t> was_in(carry && !before.empty() ? before.back() + 1 : 0, 0);
    if (carry)
      for (const unsigned int o : before)
        was_in[o] = 1;
    std::vector<unsigned int> points;
    unsigned int              differ = 0;
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (!is_virtual(i))
        {
          // An extra point (force blending's node point) may sit in another cell than before.
          const unsigned int o    = carry && !cloud.is_extra(i) ? previous_point[i] : numbers::invalid_unsigned_int;
          const bool         kept = o != numbers::invalid_unsigned_int;
          const bool         in   = kept ? o < was_in.size() && was_in[o] : in_region(region, cloud.position(i), cloud.cell[i]);
          if (kept && check_kept_families && in != in_region(region, cloud.position(i), cloud.cell[i]))
            ++differ;
          if (in)
            points.push_back(i);
        }
    if (carry && check_kept_families)
      {
        differ = Utilities::MPI::sum(differ, comm);
        AssertThrow(differ == 0, ExcMessage("Adaptivity/Check kept families: region '" + region + "' carried over "
                                            "through a conversion differs from a new test at " +
                                            std::to_string(differ) + " points"));
      }
    return points;
  }

  void
  Discretization::check_region_expressions() const
  {
    std::vector<const Expression *> expressions;
    for (const auto &[name, region] : regions)
      expressions.push_back(region->user_expression());
    check_finite(expressions, comm);
  }

  int
  Discretization::block_of_cell(const CellIterator &cell) const
  {
    if (!converted.empty() && converted[cell->active_cell_index()])
      return converted_block;
    return claiming_block(cell);
  }

  int
  Discretization::claiming_block(const CellIterator &cell) const
  {
    for (unsigned int b = 0; b < blocks.size(); ++b)
      {
        const Block &block = blocks[b];
        if (!block.region.empty())
          {
            if (in_region(block.region, cell->center(), cell))
              return b;
          }
        else if (std::find(block.material_ids.begin(), block.material_ids.end(), cell->material_id()) !=
                 block.material_ids.end())
          return b;
      }
    return -1;
  }

  void
  Discretization::number_dofs()
  {
    // A cell's element is its block's as the deck claims it, converted or
    // not: the numbering of a mesh holds through its conversions
    // (is_fe_cell() tells the converted cells). deal.II numbers every DoF
    // again when one cell's element changes, three times as long with two
    // elements as with one (hp unification), about 0.3 s at 100,000 cells.
    if (dofs_numbered)
      return;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const int b = claiming_block(cell);
          cell->set_active_fe_index(b >= 0 && blocks[b].continuum ? blocks[b].fe_degree : 0);
        }
    dof_handler.distribute_dofs(fe);
    dofs_numbered = true;
  }

  void
  Discretization::check_blocks_have_cells() const
  {
    // Per block: the cells it claims, and the cells its own criterion holds
    // (region or material ids), whether or not an earlier block claims them.
    const auto holds = [this](const Block &block, const CellIterator &cell) {
      return block.region.empty() ?
               std::find(block.material_ids.begin(), block.material_ids.end(), cell->material_id()) !=
                 block.material_ids.end() :
               in_region(block.region, cell->center(), cell);
    };
    std::vector<unsigned int> claimed(blocks.size(), 0), held(blocks.size(), 0);
    std::vector<int>          first_claimer(blocks.size(), -1);
    std::set<unsigned int>    ids;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          ids.insert(cell->material_id());
          const int b = block_of_cell(cell);
          if (b >= 0)
            ++claimed[b];
          for (unsigned int k = 0; k < blocks.size(); ++k)
            if (int(k) != b && holds(blocks[k], cell))
              {
                ++held[k];
                if (b >= 0 && (first_claimer[k] < 0 || b < first_claimer[k]))
                  first_claimer[k] = b;
              }
        }
    Utilities::MPI::sum(claimed, comm, claimed);
    Utilities::MPI::sum(held, comm, held);
    for (auto &b : first_claimer)
      b = -Utilities::MPI::max(-(b < 0 ? int(blocks.size()) : b), comm);
    const std::set<unsigned int> all_ids = Utilities::MPI::compute_set_union(ids, comm);
    for (unsigned int k = 0; k < blocks.size(); ++k)
      if (claimed[k] == 0)
        {
          const Block &block = blocks[k];
          const std::string path = "Blocks/" + block.name;
          std::string       why;
          if (held[k] > 0 && first_claimer[k] < int(blocks.size()))
            why = "every cell its " + std::string(block.region.empty() ? "Material ids" : "Region '" + block.region + "'") +
                  " holds is claimed by block '" + blocks[first_claimer[k]].name +
                  "', listed before it in Blocks/Names (a cell belongs to the first block that claims it): list '" +
                  block.name + "' first, or give '" + blocks[first_claimer[k]].name + "' a Region that leaves these cells out";
          else if (block.region.empty())
            {
              std::string want, have;
              for (const auto id : block.material_ids)
                want += (want.empty() ? "" : ", ") + std::to_string(id);
              for (const auto id : all_ids)
                have += (have.empty() ? "" : ", ") + std::to_string(id);
              why = "no cell has Material ids " + want + " (the mesh's material ids: " + have +
                    "): fix " + path + "/Material ids or set " + path + "/Region";
            }
          else
            why = "no cell centre lies in its Region '" + block.region + "': check Discretization/Regions/" +
                  block.region + " against the mesh's extent";
          AssertThrow(false,
                      ExcMessage(path + ": the block holds no cell, so its material and settings would be "
                                        "silently unused: " + why + "; or remove it from Blocks/Names"));
        }
  }

  void
  Discretization::setup()
  {
    {
      TimerOutput::Scope t(timer, "setup: mesh and points");
      // The size before allocating it (size_check.cc): a built-in scene from
      // its parameters, a Gmsh mesh once read (bounded by the file's size).
      const AvailableMemory available = available_memory(comm);
      report_p4est_out_of_memory();
      check_scene_size(available);
      scene.create_triangulation(triangulation);
      SceneGeometry::Lattice lattice;
      if (!scene.geometry->lattice(lattice)) // known once made: a mesh file
        check_mesh_size(available, "the mesh", scene.geometry->cells_key());
      for (const auto &name : scene.refinement_regions)
        AssertThrow(regions.count(name) || name == "All",
                    ExcMessage("Discretization/Refinement regions: '" + name +
                               "' is not defined in Discretization/Regions/Names"));
      const unsigned int most =
        scene.refinement_levels.empty() ? 0 :
                                          *std::max_element(scene.refinement_levels.begin(), scene.refinement_levels.end());
      // The scene may already refine a coarser mesh globally (a box of
      // 2^k cells): count the levels from the scene's cells.
      int base = std::numeric_limits<int>::max();
      for (const auto &cell : triangulation.active_cell_iterators())
        if (cell->is_locally_owned())
          base = std::min(base, cell->level());
      base = -Utilities::MPI::max(-base, comm);
      // The deepest level a cell can reach: p8est counts at most P8EST_QMAXLEVEL.
      // (Refinement levels <= 6 and a box's own <= 6: a guard for larger ones.)
      const int deepest = base + int(most);
      AssertThrow(most == 0 || deepest <= 18,
                  ExcMessage("Discretization/Refinement levels: the cells would reach refinement level " +
                             std::to_string(deepest) + " (the scene's own " + std::to_string(base) + " plus " +
                             std::to_string(most) + "), beyond p4est's limit P8EST_QMAXLEVEL = 18: use fewer levels"));
      // Region All refines every cell: 8^levels times the cells, known now.
      unsigned int everywhere = 0;
      for (unsigned int r = 0; r < scene.refinement_regions.size(); ++r)
        if (scene.refinement_regions[r] == "All")
          everywhere = std::max(everywhere, scene.refinement_levels[r]);
      if (everywhere > 0)
        check_mesh_size(available,
                        "refining every cell " + std::to_string(everywhere) + " times (region All, to level " +
                          std::to_string(base + everywhere) + ")",
                        "Discretization/Refinement levels", std::pow(8.0, everywhere));
      for (unsigned int level = 0; level < most; ++level)
        {
          for (const auto &cell : dof_handler.active_cell_iterators())
            if (cell->is_locally_owned())
              for (unsigned int r = 0; r < scene.refinement_regions.size(); ++r)
                if (scene.refinement_levels[r] > level && cell->level() == base + int(level) &&
                    in_region(scene.refinement_regions[r], cell->center(), cell))
                  cell->set_refine_flag();
          // 8 cells for each flagged one: the size before p4est allocates it.
          check_mesh_size(available,
                          "refinement pass " + std::to_string(level + 1) + " of " + std::to_string(most) +
                            " (to level " + std::to_string(base + level + 1) + ")",
                          "Discretization/Refinement levels");
          triangulation.execute_coarsening_and_refinement();
        }
      // Without automatic repartitioning, the partition of the refined mesh
      // p4est would have made after the last pass.
      if (conversions_refine && most > 0)
        triangulation.repartition();
      check_region_expressions();
      if (most > 0)
        check_mesh_size(available, "the refined mesh", "Discretization/Refinement levels");
    }
    build_points_and_bonds();

    // p4est gives every rank the same number of cells, but a step costs
    // about one unit per bond, and points near a free surface or in a small
    // horizon have fewer bonds. Repartition with the family size as the cell
    // weight and build again when the bonds are out of balance by more than 1%.
    if (Utilities::MPI::n_mpi_processes(comm) > 1)
      {
        const auto balance = Utilities::MPI::min_max_avg(double(bonds.n_bonds()), comm);
        if (balance.max > 1.01 * balance.avg)
          {
            {
              TimerOutput::Scope t(timer, "setup: mesh and points");
              repartition_by_work();
            }
            unbalanced_bonds = 100 * (balance.max / balance.avg - 1);
            build_points_and_bonds();
          }
      }
    check_isolated_points();
  }

  void
  Discretization::set_cell_weights()
  {
    // A cell's weight: its bonds plus a few for the per-point work (time
    // integration, ghost exchange); cells without a point: 1.
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        cell->set_user_index(1);
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      {
        const unsigned int weight = bonds.offsets[i + 1] - bonds.offsets[i] + 4;
        // Virtual points share their FE cell.
        cloud.cell[i]->set_user_index(is_virtual(i) ? cloud.cell[i]->user_index() + weight : weight);
      }
  }

  double
  Discretization::work_imbalance() const
  {
    double work = triangulation.n_locally_owned_active_cells();
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      work += bonds.offsets[i + 1] - bonds.offsets[i] + 4;
    const auto balance = Utilities::MPI::min_max_avg(work, comm);
    return balance.avg > 0 ? balance.max / balance.avg - 1 : 0.0;
  }

  void
  Discretization::repartition_by_work()
  {
    set_cell_weights();
    repartition_by_cell_weights();
  }

  void
  Discretization::repartition_by_cell_weights()
  {
    const auto connection = triangulation.signals.weight.connect(
      [](const Triangulation<dim>::cell_iterator &cell, const Triangulation<dim>::CellStatus) -> unsigned int {
        return cell->user_index();
      });
    triangulation.repartition();
    connection.disconnect();
  }

  void
  Discretization::rebuild_points_and_bonds()
  {
    setup_warnings.clear();
    build_points_and_bonds();
    if (previous_families != nullptr && check_kept_families)
      compare_with_searched_families();
    check_isolated_points();
  }

  std::vector<std::pair<PointKey, std::vector<PointKey>>>
  Discretization::families_by_key() const
  {
    std::vector<std::pair<PointKey, std::vector<PointKey>>> families(cloud.n_owned());
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      {
        families[i].first = cloud.key[i];
        for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
          families[i].second.push_back(cloud.key[bonds.neighbor[b]]);
      }
    std::sort(families.begin(), families.end());
    return families;
  }

  std::vector<std::pair<PointKey, std::vector<double>>>
  Discretization::coupling_by_key() const
  {
    // Per owned point its blending weight; per owned FE cell (by its key)
    // its FE weight and levels.
    std::vector<std::pair<PointKey, std::vector<double>>> band;
    if (!has_continuum)
      return band;
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      band.push_back({cloud.key[i], {point_alpha[i]}});
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && is_fe_cell(cell))
        band.push_back({cell->id().template to_binary<dim>(),
                        {-1.0, cell_fe_weight[cell->active_cell_index()], double(cell_virtual[cell->active_cell_index()])}});
    std::sort(band.begin(), band.end());
    return band;
  }

  void
  Discretization::compare_with_searched_families()
  {
    const auto         kept      = families_by_key();
    const auto         kept_band = coupling_by_key();
    std::vector<std::uint8_t> kept_flags = bonds.kept; // the log's share: what keeping kept (and was checked)
    std::vector<unsigned int> unchanged  = previous_point; // what the rebuild's later steps carry over (and check)
    const PreviousFamilies *previous = previous_families;
    const PreviousCoupling *coupling = previous_coupling;
    previous_families = nullptr;
    previous_coupling = nullptr;
    build_points_and_bonds();
    previous_families = previous;
    previous_coupling = coupling;
    bonds.kept        = std::move(kept_flags);
    previous_point    = std::move(unchanged);
    const auto   searched  = families_by_key();
    std::vector<PointKey> different; // sorted, as the families are
    for (std::size_t k = 0; k < searched.size(); ++k)
      if (k >= kept.size() || kept[k] != searched[k])
        different.push_back(searched[k].first);
    const unsigned int band_differs = Utilities::MPI::sum(static_cast<unsigned int>(kept_band != coupling_by_key()), comm);
    AssertThrow(band_differs == 0,
                ExcMessage("Adaptivity/Check kept families: the coupling band kept through a conversion (the FE "
                           "cells' weights and virtual points, the points' blending weights) differs from a new "
                           "search on " + std::to_string(band_differs) + " ranks: the kept band is wrong"));
    BestPoint first(BestPoint::Order::smallest); // the differing point of the smallest id
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (std::binary_search(different.begin(), different.end(), cloud.key[i]))
        first.consider(double(cloud.gid[i]), cloud.gid[i], &cloud.X[dim * i]);
    const std::size_t extra = kept.size() > searched.size() ? kept.size() - searched.size() : 0;
    const unsigned int total = Utilities::MPI::sum(static_cast<unsigned int>(different.size() + extra), comm);
    const BestPoint    where = first.global(comm);
    if (total == 0)
      return;
    AssertThrow(false, ExcMessage("Adaptivity/Check kept families: " + std::to_string(total) +
                                  " families kept through a conversion differ from a new search (the first at " +
                                  where.describe() + "): the kept families are wrong"));
  }

  void
  Discretization::check_cell_volumes() const
  {
    // The vertices carry about 16 digits of their distance from the origin
    // and the volume is computed from their differences (hexahedron.h): a
    // cell smaller than about 1e-10 of its distance has lost its shape to
    // rounding. The message names the bad cell smallest relative to it.
    unsigned int bad_volume = 0;
    BestPoint    smallest(BestPoint::Order::smallest);
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (!(cloud.volume[i] > 0))
        {
          ++bad_volume;
          const double *x        = &cloud.X[dim * i];
          double        distance = 0;
          for (unsigned int d = 0; d < dim; ++d)
            distance += x[d] * x[d];
          distance = std::sqrt(distance);
          smallest.consider(cloud.cell[i]->diameter() / std::max(distance, std::numeric_limits<double>::min()),
                            cloud.gid[i], x);
        }
    bad_volume = Utilities::MPI::sum(bad_volume, comm);
    if (bad_volume == 0)
      return;
    const BestPoint worst = smallest.global(comm);
    AssertThrow(false,
                ExcMessage(std::to_string(bad_volume) + " cells have zero or negative volume (the cell of " +
                           worst.describe() + "): " +
                           (worst.value < 1e-10 ?
                              "its size is " + sci(worst.value, 2) + " of its distance from the origin, below "
                              "the resolution of a double there (Box and Text file points need 1e-10): place "
                              "the body nearer the origin or use other units" :
                              std::string("the mesh is degenerate or inverted"))));
  }

  void
  Discretization::build_points_and_bonds()
  {
    {
      TimerOutput::Scope t(timer, "setup: mesh and points");

      const auto block_of = [this](const CellIterator &cell) { return block_of_cell(cell); };
      number_dofs();

      double max_horizon = 0;
      for (const auto &b : blocks)
        max_horizon = std::max(max_horizon, b.horizon);
      // Free the previous partition's points and bonds first: a rebuild must
      // not raise the peak memory.
      cloud             = PointCloud();
      bonds             = Bonds();
      cloud.periodicity = scene.periodicity(triangulation);
      AssertThrow(!(has_continuum && cloud.periodicity.any()),
                  ExcMessage("Discretization/Periodic directions: not available with continuum blocks, whose FE "
                             "field would need periodic constraints: make every block Peridynamic"));
      if (has_continuum)
        build_coupled_cloud(block_of, max_horizon);
      else
        cloud.build(dof_handler, block_of, max_horizon, comm, {}, scene.partial_volumes);

      if (cloud.n_global() == 0 && !has_continuum)
        {
          std::set<unsigned int> ids;
          for (const auto &cell : triangulation.active_cell_iterators())
            if (cell->is_locally_owned())
              ids.insert(cell->material_id());
          std::string list;
          for (const auto id : ids)
            list += (list.empty() ? "" : ", ") + std::to_string(id);
          AssertThrow(false, ExcMessage("no cell belongs to any block: check Blocks/*/Material ids "
                                        "or Region (material ids in the mesh on rank 0: " + list + ")"));
        }
      if (converted.empty()) // after a conversion a convertible block may have no cell left
        check_blocks_have_cells();
      check_cell_volumes();
    }
    {
      TimerOutput::Scope        t(timer, "setup: neighbor search");
      std::vector<double>       horizon(blocks.size());
      std::vector<std::uint8_t> rigid(blocks.size());
      for (unsigned int b = 0; b < blocks.size(); ++b)
        horizon[b] = blocks[b].horizon, rigid[b] = blocks[b].rigid;
      PreviousFamilies previous;
      previous_point.clear();
      if (previous_families != nullptr && previous_families->nothing_moved)
        {
          // A rebalance: a point that stayed on this rank is as it was.
          previous = *previous_families;
          previous_point.resize(cloud.n_owned());
          for (unsigned int i = 0; i < cloud.n_owned(); ++i)
            previous_point[i] = find_by_key(*previous.keys, *previous.order, cloud.key[i]);
        }
      else if (previous_families != nullptr)
        previous = with_changed_points(*previous_families, horizon);
      bonds = find_families(cloud, horizon, comm, cloud.max_cell_radius, rigid,
                            previous_families != nullptr ? &previous : nullptr);
      if (scene.partial_volumes)
        {
          compute_partial_volumes(cloud, bonds, horizon);
          cloud.cell_vertices = std::vector<double>(); // set-up only
        }
      if (!bond_filters.empty())
        apply_bond_filters();
      if (has_continuum && !force_blending)
        drop_unweighted_bonds();
      if (!initial_damage.empty())
        apply_initial_damage();
    }
    converted_when_built = converted;
  }

  PreviousFamilies
  Discretization::with_changed_points(const PreviousFamilies &previous, const std::vector<double> &horizon)
  {
    // A point changed if it is new, gone, moved, or changed block or
    // blending weight (which decides drop_unweighted_bonds()); a family
    // can change only within a search reach of a changed point.
    PreviousFamilies                   result = previous;
    std::vector<Point<dim>>            changed;
    const std::vector<PointKey>     &keys  = previous.compared_keys != nullptr ? *previous.compared_keys : *previous.keys;
    const std::vector<unsigned int> &order = previous.compared_order != nullptr ? *previous.compared_order : *previous.order;
    const unsigned int                 n     = cloud.n_owned();
    std::vector<PointKey>              now(cloud.key.begin(), cloud.key.begin() + n);
    std::sort(now.begin(), now.end());
    previous_point.assign(n, numbers::invalid_unsigned_int);
    for (unsigned int i = 0; i < n; ++i)
      {
        const unsigned int old  = find_by_key(keys, order, cloud.key[i]);
        bool               same = old != numbers::invalid_unsigned_int && (*previous.block)[old] == cloud.block[i] &&
                    (*previous.alpha)[old] == point_alpha[i];
        for (unsigned int d = 0; same && d < dim; ++d)
          same = (*previous.positions)[dim * old + d] == cloud.X[dim * i + d];
        if (!same)
          changed.push_back(cloud.position(i));
        else // (after a move between ranks the compared points are not the rank's own)
          previous_point[i] = previous.compared_keys == nullptr ?
                                old :
                                find_by_key(*previous.keys, *previous.order, cloud.key[i]);
      }
    for (unsigned int k = 0; k < keys.size(); ++k)
      if (!std::binary_search(now.begin(), now.end(), keys[k]))
        {
          Point<dim> x;
          for (unsigned int d = 0; d < dim; ++d)
            x[d] = (*previous.positions)[dim * k + d];
          changed.push_back(x);
        }
    for (const auto &part : Utilities::MPI::all_gather(comm, changed))
      result.changed.insert(result.changed.end(), part.begin(), part.end());
    result.radius = longest_bond(horizon);
    return result;
  }

  double
  Discretization::longest_bond(const std::vector<double> &horizon) const
  {
    double largest = 0;
    for (const double h : horizon)
      largest = std::max(largest, h);
    return (1 + 1e-6) * (largest * (1 + horizon_tolerance) + cloud.max_cell_radius);
  }

  namespace
  {
    /// An initial damage region that holds every point breaks every bond, as
    /// Region = All would (refused when read, InitialDamage): the same Error.
    /// @p inside: 1 at the owned points in the region. Collective.
    void
    refuse_region_of_every_point(const InitialDamage &entry, const LinearAlgebra::distributed::Vector<double> &inside,
                                 const types::global_dof_index n_global, const MPI_Comm comm)
    {
      double n_inside = 0;
      for (unsigned int i = 0; i < inside.locally_owned_size(); ++i)
        n_inside += inside.local_element(i);
      n_inside = Utilities::MPI::sum(n_inside, comm);
      AssertThrow(n_global == 0 || n_inside < n_global,
                  ExcMessage("Discretization/Initial damage/" + entry.name + "/Region: '" + entry.region +
                             "' holds all " + std::to_string(n_global) + " points of the body, so it would "
                             "break every bond, as 'All' would; name a region of part of the body"));
    }
  } // namespace

  void
  Discretization::apply_initial_damage()
  {
    const unsigned int n = cloud.n_owned();
    initially_broken.assign(bonds.n_bonds(), 0);
    initially_broken_bonds.assign(initial_damage.size(), 0);
    const bool         periodic = cloud.periodicity.any();
    LinearAlgebra::distributed::Vector<double> inside; // Type::region: 1 at the points in the region, ghosted
    for (unsigned int d = 0; d < initial_damage.size(); ++d)
      {
        const InitialDamage &entry = initial_damage[d];
        if (entry.type == InitialDamage::Type::region)
          {
            // Both owners of a bond must know whether either end is inside.
            inside.reinit(cloud.scalar_partitioner);
            for (unsigned int i = 0; i < n; ++i)
              inside.local_element(i) = in_region(entry.region, cloud.position(i), cloud.cell[i]) ? 1.0 : 0.0;
            inside.update_ghost_values();
            refuse_region_of_every_point(entry, inside, cloud.n_global(), comm);
          }
        for (unsigned int i = 0; i < n; ++i)
          for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
            {
              const unsigned int j = bonds.neighbor[b];
              bool               breaks;
              if (entry.type == InitialDamage::Type::region)
                breaks = inside.local_element(i) > 0 || inside.local_element(j) > 0;
              else
                {
                  // As apply_bond_filters(): across a periodic face either image's cut cuts.
                  const Point<dim> xi = cloud.position(i), xj = cloud.position(j);
                  const auto       e  = cloud.bond_vector(i, j);
                  breaks = periodic ? entry.plane.cuts(xi, xi + e) || entry.plane.cuts(xj - e, xj) :
                                      entry.plane.cuts(xi, xj);
                }
              if (breaks && !initially_broken[b])
                {
                  initially_broken[b] = 1;
                  ++initially_broken_bonds[d];
                }
            }
      }
    check_region_expressions();
    Utilities::MPI::sum(initially_broken_bonds, comm, initially_broken_bonds);
  }

  void
  Discretization::apply_bond_filters()
  {
    filtered_bonds.assign(bond_filters.size(), 0);
    const bool periodic = cloud.periodicity.any();
    // A family whose point lies farther from every filter than its longest
    // bond can reach (the largest horizon and the search's extra reach)
    // cannot be cut: its bonds are not tested one by one.
    const double              longest = longest_bond(bonds.block_horizon);
    std::vector<std::uint8_t> near(cloud.n_owned(), 1);
    if (!periodic)
      for (unsigned int i = 0; i < cloud.n_owned(); ++i)
        near[i] = std::any_of(bond_filters.begin(), bond_filters.end(),
                              [&](const BondFilter &f) { return f.distance(cloud.position(i)) <= longest; });
    bonds.keep_if(cloud.n_owned(), [&](const unsigned int i, const unsigned int j) {
      if (!near[i] || (!bonds.kept.empty() && bonds.kept[i]))
        return true; // out of reach, or cut before (filtered_bonds counts the searched families)
      // Across a periodic face the bond has two images, one at each end's
      // face; either cut cuts it, so that both owners decide alike.
      const Point<dim> xi = cloud.position(i), xj = cloud.position(j);
      const auto       e  = cloud.bond_vector(i, j);
      for (unsigned int f = 0; f < bond_filters.size(); ++f)
        if (periodic ? bond_filters[f].cuts(xi, xi + e) || bond_filters[f].cuts(xj - e, xj) :
                       bond_filters[f].cuts(xi, xj))
          {
            ++filtered_bonds[f];
            return false;
          }
      return true;
    });
    Utilities::MPI::sum(filtered_bonds, comm, filtered_bonds);
  }

  void
  Discretization::check_isolated_points()
  {
    // A point without a neighbor carries no load: it moves freely under its
    // conditions (a body force, a prescribed displacement, an initial
    // velocity), as Peridigm moves it. Said, with how many, so that a
    // horizon below the spacing in part of a mesh does not pass unnoticed;
    // a body of which every point is one has no bond at all, which is a
    // mistake (a horizon below the spacing everywhere), not a scene. In a
    // block in contact a point may be a free particle, and a rigid block has
    // no bonds: neither counts.
    unsigned int candidates = 0, isolated = 0;
    BestPoint    first(BestPoint::Order::smallest); // the smallest global id
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (!is_virtual(i) && // see drop_unweighted_bonds()
          !contact.involves(blocks[cloud.block[i]].name) && !blocks[cloud.block[i]].rigid)
        {
          ++candidates;
          if (bonds.offsets[i + 1] == bonds.offsets[i])
            {
              ++isolated;
              first.consider(0, cloud.gid[i], &cloud.X[dim * i], BestPoint::Kind::point, cloud.block[i]);
            }
        }
    unsigned int counts[2] = {candidates, isolated};
    Utilities::MPI::sum(ArrayView<const unsigned int>(counts, 2), comm, ArrayView<unsigned int>(counts, 2));
    const unsigned int total = counts[1];
    if (total == 0)
      return;
    const BestPoint p     = first.global(comm);
    const Block    &block = blocks[static_cast<unsigned int>(p.tag)];
    const std::string where = "the first " + p.describe() + " in block '" + block.name + "' with horizon " +
                              sci(block.horizon);
    AssertThrow(total < counts[0],
                ExcMessage(std::to_string(total) + " points have no neighbor within the horizon, " + where +
                           ": no point of the body has a bond; the horizon must exceed the point spacing (Blocks/" +
                           block.name + "/Horizon or Discretization/Horizon)"));
    setup_warnings.push_back(std::to_string(total) + " of " + std::to_string(counts[0]) +
                             " points have no neighbor within the horizon, " + where +
                             ": each has no bond and moves freely under its conditions (body force, prescribed "
                             "displacement, initial velocity; a quasistatic solve holds it where it is); a horizon "
                             "above the point spacing bonds them (Blocks/" + block.name +
                             "/Horizon or Discretization/Horizon)");
  }

  double
  Discretization::point_spacing() const
  {
    double h = std::numeric_limits<double>::max();
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (!is_virtual(i))
        h = std::min(h, std::cbrt(cloud.volume[i]));
    return Utilities::MPI::min(h, comm);
  }

  void
  Discretization::build_coupled_cloud(const std::function<int(const CellIterator &)> &block_of, const double max_horizon)
  {
    // The PD points within reach of this rank's FE cells: one probe point per
    // FE cell makes the ghost exchange bring them.
    // The largest FE and PD cells, in one pass and one reduction.
    double largest[2] = {0, 0};
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          double &of_kind = largest[is_fe_cell(cell) ? 0 : 1];
          of_kind         = std::max(of_kind, cell->diameter());
        }
    Utilities::MPI::max(ArrayView<const double>(largest, 2), comm, ArrayView<double>(largest, 2));
    const double largest_cell = largest[0];
    // Force blending's virtual points reach a horizon further (below). An
    // FE cell that keeps its band from before a conversion (kept_coupling())
    // needs no probe.
    const std::vector<unsigned int> kept  = kept_coupling(max_horizon, largest[1]);
    const auto                      keeps = [&](const CellIterator &cell) {
      return !kept.empty() && kept[cell->active_cell_index()] != numbers::invalid_unsigned_int;
    };
    const int    probe = blocks.size();
    const double reach = (1 + blending_width + (force_blending ? 1 : 0)) * max_horizon + largest_cell;
    PointCloud   nearby;
    nearby.build(dof_handler,
                 [&](const CellIterator &cell) -> int {
                   const int b = block_of(cell);
                   return b < 0 ? -1 : !blocks[b].continuum ? b : keeps(cell) ? -1 : probe;
                 },
                 reach, comm, {}, force_blending, {}, &cell_geometry);
    std::vector<std::pair<Point<dim>, unsigned int>> pd;
    for (unsigned int i = 0; i < nearby.n_local(); ++i)
      if (nearby.block[i] != probe)
        pd.emplace_back(nearby.position(i), i);
    const auto tree = pack_rtree(pd);

    // Distance to the interface: to the nearest PD point less half its
    // spacing; alpha falls from 1 to 0 over the band (a step without one).
    struct Nearest
    {
      double distance, band, horizon, volume; // volume: of the nearest PD point
    };
    const auto nearest = [&](const Point<dim> &x) -> Nearest {
      for (const auto &p : tree | bgi::adaptors::queried(bgi::nearest(x, 1)))
        {
          const unsigned int i = p.second;
          const double       h = blocks[nearby.block[i]].horizon;
          return {std::max(0.0, x.distance(p.first) - 0.5 * std::cbrt(nearby.volume[i])), blending_width * h, h,
                  nearby.volume[i]};
        }
      return {std::numeric_limits<double>::max(), 0, 0, 1};
    };
    const auto alpha = [](const Nearest &n) {
      return n.band > 0 ? std::max(0.0, 1 - n.distance / n.band) : 0.0;
    };

    cell_fe_weight.assign(triangulation.n_active_cells(), 1.0);
    cell_virtual.assign(triangulation.n_active_cells(), 0);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && is_fe_cell(cell))
        {
          if (keeps(cell))
            {
              const auto &before = previous_coupling->cells[kept[cell->active_cell_index()]];
              cell_fe_weight[cell->active_cell_index()] = before.fe_weight;
              cell_virtual[cell->active_cell_index()]   = before.levels;
              continue;
            }
          const Nearest n = nearest(cell->center());
          // Force blending weights forces, not the FE energy.
          cell_fe_weight[cell->active_cell_index()] = force_blending ? 1 : 1 - alpha(n);
          // Virtual points serve up to a horizon beyond the band, at about
          // the nearest PD point's spacing (auto levels). Force blending
          // evaluates the PD force at the band's nodes, and the neighbors in
          // their families need complete families of their own (an LPS
          // dilatation, a correspondence deformation gradient): two horizons.
          if (n.distance - 0.5 * cell->diameter() <= virtual_point_reach(n.horizon) * (1 + 1e-9))
            cell_virtual[cell->active_cell_index()] = 1 + virtual_levels(cell_geometry(cell).second, n.volume);
        }

    cloud.build(dof_handler,
                [&](const CellIterator &cell) -> int {
                  const int b = block_of(cell);
                  return b >= 0 && blocks[b].continuum && !cell_virtual[cell->active_cell_index()] ? -1 : b;
                },
                max_horizon, comm,
                [&](const CellIterator &cell) -> unsigned int {
                  return is_fe_cell(cell) ? cell_virtual[cell->active_cell_index()] - 1 : 0;
                },
                scene.partial_volumes,
                force_blending ? make_node_points(nearby, probe, block_of, max_horizon) :
                                 std::vector<PointCloud::ExtraPoint>(),
                &cell_geometry);
    // Force blending: every point carries its full PD energy (the PD force
    // at a PD point or a node is the unweighted one).
    // A kept cell's virtual points are made in the order they were (the
    // lattice's), so their weights follow one after the other.
    point_alpha.assign(cloud.n_owned(), 1.0);
    if (!force_blending)
      for (unsigned int i = 0, next = 0; i < cloud.n_owned(); ++i)
        if (blocks[cloud.block[i]].continuum)
          {
            if (!keeps(cloud.cell[i]))
              {
                point_alpha[i] = alpha(nearest(cloud.position(i)));
                continue;
              }
            const auto &before = previous_coupling->cells[kept[cloud.cell[i]->active_cell_index()]];
            if (i == 0 || cloud.cell[i - 1] != cloud.cell[i])
              next = before.first_alpha;
            point_alpha[i] = previous_coupling->alpha[next++];
          }
    node_points.clear();
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (cloud.is_extra(i))
        node_points.push_back(i);
  }

  PreviousCoupling
  Discretization::record_coupling() const
  {
    PreviousCoupling before;
    if (!has_continuum || force_blending)
      return before;
    // Each cell's virtual points follow one another in the cloud.
    std::vector<unsigned int> first_point(triangulation.n_active_cells(), numbers::invalid_unsigned_int);
    for (unsigned int i = cloud.n_owned(); i-- > 0;)
      if (is_virtual(i))
        first_point[cloud.cell[i]->active_cell_index()] = i;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && was_fe_cell(cell))
        {
          const unsigned int c = cell->active_cell_index();
          before.cells.push_back({cell->id(), cell_fe_weight[c], cell_virtual[c], unsigned(before.alpha.size())});
          if (cell_virtual[c] > 0)
            {
              const unsigned int n = 1u << (dim * (cell_virtual[c] - 1));
              before.alpha.insert(before.alpha.end(), point_alpha.begin() + first_point[c],
                                  point_alpha.begin() + first_point[c] + n);
            }
        }
    std::sort(before.cells.begin(), before.cells.end());
    return before;
  }

  std::vector<unsigned int>
  Discretization::kept_coupling(const double max_horizon, const double largest_pd_cell) const
  {
    std::vector<unsigned int> kept;
    if (previous_coupling == nullptr || force_blending)
      return kept;
    // A cell keeps its band if no PD point can have appeared nearer to it
    // than its band reaches: then either its nearest PD point is the one it
    // had, or both that and the new one are too far to give it virtual
    // points or a weight. The reach plus half a PD spacing (the distance
    // is taken from the nearest point less half its spacing) plus half
    // the cell (its diameter: the centre of a distorted cell may lie off
    // its middle), bounded above with the largest PD cell.
    const double reach = (1 + 1e-6) * (virtual_point_reach(max_horizon) + largest_pd_cell) + previous_coupling->radius;
    const auto   tree  = pack_rtree(previous_coupling->centres);
    std::vector<Point<dim>> nearest; // reused
    kept.assign(triangulation.n_active_cells(), numbers::invalid_unsigned_int);
    const auto &cells = previous_coupling->cells;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && is_fe_cell(cell))
        {
          const PreviousCoupling::Cell key{cell->id(), 0, 0, 0};
          const auto                   at = std::lower_bound(cells.begin(), cells.end(), key);
          if (at == cells.end() || at->id != key.id)
            continue; // new here: refined, or moved from another rank
          nearest.clear();
          tree.query(bgi::nearest(cell->center(), 1), std::back_inserter(nearest));
          if (nearest.empty() || nearest[0].distance(cell->center()) > reach + cell->diameter())
            kept[cell->active_cell_index()] = at - cells.begin();
        }
    return kept;
  }

  std::vector<PointCloud::ExtraPoint>
  Discretization::make_node_points(const PointCloud &nearby, const int probe,
                                   const std::function<int(const CellIterator &)> &block_of, const double max_horizon)
  {
    // The PD cells near this rank's FE cells, as boxes around their vertices.
    std::vector<std::pair<BoundingBox<dim>, unsigned int>> pd_cells;
    for (unsigned int i = 0; i < nearby.n_local(); ++i)
      if (nearby.block[i] != probe)
        {
          std::vector<Point<dim>> v(8);
          for (unsigned int k = 0; k < 8; ++k)
            for (unsigned int d = 0; d < dim; ++d)
              v[k][d] = nearby.cell_vertices[8 * dim * i + dim * k + d];
          pd_cells.emplace_back(BoundingBox<dim>(v), i);
        }
    const auto tree = pack_rtree(pd_cells);
    // A node on a PD cell's closure (distance 0 to its box, up to rounding)
    // has an FE force from one side only: its alpha is exactly 1.
    const auto weight = [&](const Point<dim> &x, const double size) {
      double           nearest = std::numeric_limits<double>::max(), horizon = 0;
      BoundingBox<dim> around(std::make_pair(x, x));
      around.extend(blending_width * max_horizon + size);
      for (const auto &c : tree | bgi::adaptors::queried(bgi::intersects(around)))
        {
          // Distance from x to the box (deal.II 9.4's BoundingBox has no distance()).
          const auto &[lo, hi] = c.first.get_boundary_points();
          double      d2       = 0;
          for (unsigned int k = 0; k < dim; ++k)
            {
              const double out = std::max({lo[k] - x[k], x[k] - hi[k], 0.0});
              d2 += out * out;
            }
          if (d2 < nearest * nearest)
            nearest = std::sqrt(d2), horizon = blocks[nearby.block[c.second]].horizon;
        }
      if (nearest <= 1e-9 * size)
        return 1.0;
      return blending_width > 0 && nearest < std::numeric_limits<double>::max() ?
               std::max(0.0, 1 - nearest / (blending_width * horizon)) :
               0.0;
    };

    AffineConstraints<double> hanging;
    IndexSet                  relevant;
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    hanging.reinit(relevant);
    DoFTools::make_hanging_node_constraints(dof_handler, hanging);
    hanging.close();
    const IndexSet                      &owned = dof_handler.locally_owned_dofs();
    std::set<types::global_dof_index>    done;
    std::vector<types::global_dof_index> dofs;
    const MappingQ1<dim>                 mapping;
    std::vector<PointCloud::ExtraPoint>  points;
    node_point_dofs.clear();
    node_point_alpha.clear();
    // The owned FE cells near PD points, then the ghost FE cells for the
    // owned DoFs on no owned FE cell (beside owned converted cells, which
    // keep their FE_Q DoFs: is_fe_cell()). Such a node lies on a PD cell.
    std::vector<std::uint8_t> on_owned_cells(owned.n_elements(), 0);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && is_fe_cell(cell))
        {
          dofs.resize(cell->get_fe().n_dofs_per_cell());
          cell->get_dof_indices(dofs);
          for (const auto dof : dofs)
            if (owned.is_element(dof))
              on_owned_cells[owned.index_within_set(dof)] = 1;
        }
    for (const bool owned_cells : {true, false})
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (!cell->is_artificial() && cell->is_locally_owned() == owned_cells && is_fe_cell(cell) &&
            (!owned_cells || cell_virtual[cell->active_cell_index()]))
          {
            const auto &fe = cell->get_fe();
            dofs.resize(fe.n_dofs_per_cell());
            cell->get_dof_indices(dofs);
            const double size = cell->minimum_vertex_distance();
            for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
              {
                // One point per node: its x component's DoF stands for it.
                const auto [component, base] = fe.system_to_component_index(i);
                if (component != 0 || !owned.is_element(dofs[i]) || hanging.is_constrained(dofs[i]) ||
                    (!owned_cells && on_owned_cells[owned.index_within_set(dofs[i])]) || !done.insert(dofs[i]).second)
                  continue;
                const Point<dim> x = mapping.transform_unit_to_real_cell(cell, fe.unit_support_point(i));
                const double     a = weight(x, size);
                if (a == 0)
                  continue;
                // A key no cell has, the same on any number of ranks.
                std::uint64_t h = 0;
                for (unsigned int d = 0; d < dim; ++d)
                  {
                    std::uint64_t bits;
                    std::memcpy(&bits, &x[d], sizeof bits);
                    h = mix64(h ^ bits);
                  }
                const std::uint64_t h2 = mix64(h);
                points.push_back({x, cell_volume(cell) / fe.n_dofs_per_cell(), static_cast<unsigned short>(block_of(cell)),
                                  PointKey{{PointCloud::extra_key, unsigned(h), unsigned(h >> 32), unsigned(h2)}}, cell});
                for (unsigned int d = 0; d < dim; ++d)
                  node_point_dofs.push_back(dofs[fe.component_to_system_index(d, base)]);
                node_point_alpha.push_back(a);
              }
          }
    return points;
  }

  void
  Discretization::drop_unweighted_bonds()
  {
    VectorType alpha(cloud.scalar_partitioner);
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      alpha.local_element(i) = point_alpha[i];
    alpha.update_ghost_values();
    bonds.keep_if(cloud.n_owned(), [&](const unsigned int i, const unsigned int j) {
      return point_alpha[i] > 0 || alpha.local_element(j) > 0;
    });
  }
} // namespace perideal
