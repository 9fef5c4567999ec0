#include <perideal/base/memory.h>
#include <perideal/discretization/size_estimate.h>
#include <perideal/neighborhood/partial_volumes.h>
#include <perideal/solver/simulation.h>
#include <perideal/base/interrupt.h>
#include <perideal/base/best_point.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/mpi.templates.h>
#include <deal.II/base/utilities.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_dgq.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/numerics/rtree.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    std::string
    format_seconds(const double s)
    {
      std::ostringstream o;
      if (s < 60)
        o << std::fixed << std::setprecision(1) << s << " s";
      else if (s < 3600)
        o << int(s) / 60 << " min " << int(s) % 60 << " s";
      else
        o << int(s) / 3600 << " h " << (int(s) % 3600) / 60 << " min";
      return o.str();
    }

    std::string
    sci(const double v, const unsigned int digits = 4)
    {
      std::ostringstream o;
      o << std::setprecision(digits) << v;
      return o.str();
    }

    std::string
    mib(const double bytes)
    {
      std::ostringstream o;
      o << std::fixed << std::setprecision(1) << bytes / 1048576.0 << " MiB";
      return o.str();
    }

    const std::vector<std::string> solver_types = {"Verlet"};

    // The automatic Verlet step keeps every point with intact bonds within
    // this fraction of the point spacing per step. A point that crosses a
    // large part of the spacing in one step outruns its neighbours' forces
    // and energy is made: two blocks meeting at Mach 2 (tests/stability/
    // impact.prm) gain 4.6% of their kinetic energy at 1.55 spacings per
    // step (the stable elastic step), 0.98% at 0.77, 0.39% at 0.39, 0.089%
    // at 0.19: about 0.02 (|v| dt/h)^2. LAMMPS' fix dt/reset limits the
    // same motion per step.
    constexpr double max_spacing_fraction = 0.2;
  } // namespace

  // ---------------------------------------------------------------- parameters

  void
  declare_parameters(ParameterHandler &prm, const DeckNames &names)
  {
    prm.enter_subsection("Discretization");
    Scene::declare_parameters(prm);
    declare_named_section(prm, "Regions", "regions (Peridigm's node sets); 'All' is always defined", names.regions,
                          [&](const std::string &) { Region::declare_parameters(prm); });
    declare_named_section(prm, "Bond filters", "bond filters: planes no bond crosses (pre-cracks, notches)",
                          names.bond_filters, [&](const std::string &) { BondFilter::declare_parameters(prm); });
    prm.leave_subsection();

    prm.enter_subsection("Materials");
    declare_names_entry(prm, "materials");
    for (const auto &[name, model] : names.materials)
      {
        prm.enter_subsection(name);
        declare_material_model_entry(prm);
        if (!model.empty())
          Registry<Material>::instance().get(model, "Materials/" + name + "/Model").declare(prm);
        prm.leave_subsection();
      }
    prm.leave_subsection();

    prm.enter_subsection("Damage models");
    declare_names_entry(prm, "damage models");
    for (const auto &[name, model] : names.damage_models)
      {
        prm.enter_subsection(name);
        declare_damage_model_entry(prm);
        if (!model.empty())
          Registry<DamageModel>::instance().get(model, "Damage models/" + name + "/Model").declare(prm);
        prm.leave_subsection();
      }
    prm.leave_subsection();

    prm.enter_subsection("Blocks");
    declare_names_entry(prm, "blocks; a cell belongs to the first block that claims it");
    for (const auto &name : names.blocks)
      {
        prm.enter_subsection(name);
        prm.declare_entry("Material", "", Patterns::Anything(), "Name of a material of Materials/Names.");
        prm.declare_entry("Damage model", "", Patterns::Anything(), "Name of a damage model of Damage models/Names; empty: no damage.");
        prm.declare_entry("Material ids", "0", Patterns::List(Patterns::Integer(0)), "The cells of the mesh with these material ids (Gmsh volume physical groups) form the block.");
        prm.declare_entry("Region", "", Patterns::Anything(), "If set, the cells whose centroid lies in this region form the block instead.");
        prm.declare_entry("Horizon", "0", Patterns::Double(0), "The block's horizon; 0: Discretization/Horizon.");
        prm.declare_entry("Type", "Peridynamic", Patterns::Selection("Peridynamic|Continuum"),
                          "Peridynamic: one PD point per cell. Continuum: FE_Q(FE degree) linear elasticity "
                          "with the material's bulk modulus, shear modulus and density; peridynamic families "
                          "reach into its cells through virtual points (doc/coupling.md). Continuum blocks "
                          "take no damage model.");
        prm.declare_entry("FE degree", "1", Patterns::Integer(1, 2), "Polynomial degree of a continuum block's FE_Q elements.");
        prm.leave_subsection();
      }
    prm.leave_subsection();

    prm.enter_subsection("Coupling");
    prm.declare_entry("Blending width", "1", Patterns::Double(0),
                      "Width of the band inside continuum blocks, in horizons, over which the energy "
                      "passes from peridynamic to finite element (the PD weight falls linearly from 1 at "
                      "the PD cells to 0); 0: a step at the interface. Wider bands give smaller ghost "
                      "forces (doc/coupling.md) and cost more virtual points.");
    prm.declare_entry("Virtual point levels", "auto", Patterns::Selection("auto|0|1|2|3"),
                      "Virtual points per continuum cell within reach of the PD points: the centroids of "
                      "its descendants this many refinements down (8^levels per cell). auto: per cell, the "
                      "levels that bring their spacing closest to that of the nearest PD point (0 for FE "
                      "cells of the PD spacing, 1 for cells twice as large).");
    prm.leave_subsection();

    declare_named_section(prm, "Boundary conditions", "initial and boundary conditions", names.conditions,
                          [&](const std::string &) { BoundaryCondition::declare_parameters(prm); });
    declare_named_section(prm, "Computes",
                          "computes: global quantities over regions, extra columns of the globals CSV",
                          names.computes, [&](const std::string &) { RegionCompute::declare_parameters(prm); });

    prm.enter_subsection("Solver");
    prm.declare_entry("Type", "Verlet", Patterns::Selection("Verlet|QuasiStatic|Newmark"),
                      "Verlet: explicit velocity-Verlet with lumped mass. QuasiStatic: Number of steps "
                      "load steps from Initial time to Final time (a pseudo-time; 0 to 1 if Final time is "
                      "not after Initial time), each solved by Newton's method (subsection Implicit). "
                      "Newmark: implicit dynamics, Number of steps equal steps from Initial time to Final "
                      "time, each solved by Newton's method (subsection Implicit).");
    prm.declare_entry("Initial time", "0", Patterns::Double(), "Start time.");
    prm.declare_entry("Final time", "0", Patterns::Double(), "End time. The number of steps is ceil((final - initial)/dt), and dt is then shortened to land on the final time exactly (Verlet steps shortened for fast points, see Verlet/Fixed dt, add steps).");
    prm.declare_entry("Number of steps", "0", Patterns::Integer(0), "If positive: run exactly this many steps of dt and ignore Final time.");
    prm.declare_entry("Energy growth limit", "10", Patterns::Double(1),
                      "Stop when the kinetic energy exceeds this factor times (initial kinetic + "
                      "strain energy + work of external forces): the run is unstable.");
    prm.declare_entry("Track dissipated energy", "false", Patterns::Bool(),
                      "With a damage model: sum the strain energy that breaking bonds release (their "
                      "energy at the state where they broke, with them intact minus without) and add it "
                      "to the closing summary's energy balance, which then checks that the run makes no "
                      "energy. Costs two more force evaluations in every step or damage solve that breaks "
                      "bonds (doc/examples/fragmenting_cylinder_reduced: time loop 23 s instead of 8.7 s).");
    prm.enter_subsection("Implicit");
    ImplicitParameters::declare_parameters(prm);
    prm.leave_subsection();
    prm.enter_subsection("Verlet");
    prm.declare_entry("Fixed dt", "0", Patterns::Double(0),
                      "Time step; 0: Safety factor times the smallest stable estimate over all points, "
                      "shortened in a step that starts with a point with intact bonds faster than 0.2 "
                      "point spacings per step (a faster one outruns its neighbours' forces and makes "
                      "energy; a fixed step that allows it is warned about).");
    prm.declare_entry("Safety factor", "0.8", Patterns::Double(0, 1), "Fraction of the stable time step used when Fixed dt is 0.");
    prm.leave_subsection();
    prm.leave_subsection();

    prm.enter_subsection("Output");
    OutputWriter::declare_parameters(prm);
    prm.leave_subsection();
  }

  void
  print_parameter_reference(std::ostream &out, const bool markdown)
  {
    DeckNames names;
    names.regions       = {"My region"};
    names.blocks        = {"My block"};
    names.conditions    = {"My condition"};
    names.computes      = {"My compute"};
    for (const auto &m : Registry<Material>::instance().all())
      names.materials["My " + m.first + " material"] = m.first;
    for (const auto &m : Registry<DamageModel>::instance().all())
      names.damage_models["My " + m.first + " model"] = m.first;
    ParameterHandler prm;
    declare_parameters(prm, names);
    auto set_names = [&](const std::vector<std::string> &path, const std::string &list) {
      for (const auto &p : path)
        prm.enter_subsection(p);
      prm.set("Names", list);
      for (unsigned int i = 0; i < path.size(); ++i)
        prm.leave_subsection();
    };
    auto join = [](const auto &map) {
      std::string s;
      for (const auto &e : map)
        s += (s.empty() ? "" : ", ") + e.first;
      return s;
    };
    set_names({"Discretization", "Regions"}, "My region");
    set_names({"Discretization", "Bond filters"}, "My filter");
    set_names({"Materials"}, join(names.materials));
    set_names({"Damage models"}, join(names.damage_models));
    set_names({"Blocks"}, "My block");
    set_names({"Boundary conditions"}, "My condition");
    for (const auto &[name, model] : names.materials)
      {
        prm.enter_subsection("Materials");
        prm.enter_subsection(name);
        prm.set("Model", model);
        prm.leave_subsection();
        prm.leave_subsection();
      }
    for (const auto &[name, model] : names.damage_models)
      {
        prm.enter_subsection("Damage models");
        prm.enter_subsection(name);
        prm.set("Model", model);
        prm.leave_subsection();
        prm.leave_subsection();
      }

    if (markdown)
      {
        out << "# Parameter reference\n\n"
            << "Generated by `pd_app --print-parameters-markdown` at build time; do not edit.\n\n"
            << "A parameter file is a deal.II ParameterHandler file. Sections that hold\n"
            << "user-named entries (regions, materials, damage models, blocks, boundary\n"
            << "conditions) list the names in `Names`; each name then has a subsection.\n"
            << "A material or damage model subsection holds `Model` and that model's keys.\n"
            << "Below, every model appears once under an example name.\n\n"
            << "Models: materials " << Registry<Material>::instance().names(", ")
            << "; damage models " << Registry<DamageModel>::instance().names(", ") << ".\n\n";
        for (const auto &m : Registry<Material>::instance().all())
          out << "- material `" << m.first << "`: " << m.second.documentation << "\n";
        for (const auto &m : Registry<DamageModel>::instance().all())
          out << "- damage model `" << m.first << "`: " << m.second.documentation << "\n";
        out << "\n```\n";
      }
    prm.print_parameters(out, ParameterHandler::PRM);
    if (markdown)
      out << "```\n";
  }

  Simulation::Simulation(const std::string &parameter_file, const MPI_Comm comm_)
    : comm(comm_)
    , pcout(std::cout, Utilities::MPI::this_mpi_process(comm_) == 0)
    , timer(pcout, TimerOutput::never, TimerOutput::wall_times)
    , triangulation(comm_)
    , fe(FESystem<dim>(FE_DGQ<dim>(0), dim), FESystem<dim>(FE_Q<dim>(1), dim), FESystem<dim>(FE_Q<dim>(2), dim))
    , dof_handler(triangulation)
    // The libraries are loaded and initialised by now: what the scene adds
    // to this is its own memory.
    , startup_memory(resident_memory_bytes())
  {
    read_parameters(parameter_file);
  }

  void
  Simulation::read_parameters(const std::string &file)
  {
    DeckNames names;
    auto      read_list = [&](ParameterHandler &prm, const std::vector<std::string> &path) {
      for (const auto &p : path)
        prm.enter_subsection(p);
      std::string where;
      for (const auto &p : path)
        where += p + "/";
      auto list = split_names(prm.get("Names"), where + "Names");
      for (unsigned int i = 0; i < path.size(); ++i)
        prm.leave_subsection();
      return list;
    };
    // Pass 1: the names.
    {
      ParameterHandler prm;
      declare_parameters(prm, names);
      parse_input_file(prm, file, false);
      names.regions    = read_list(prm, {"Discretization", "Regions"});
      names.bond_filters = read_list(prm, {"Discretization", "Bond filters"});
      names.blocks     = read_list(prm, {"Blocks"});
      names.conditions = read_list(prm, {"Boundary conditions"});
      names.computes   = read_list(prm, {"Computes"});
      for (const auto &n : read_list(prm, {"Materials"}))
        names.materials[n] = "";
      for (const auto &n : read_list(prm, {"Damage models"}))
        names.damage_models[n] = "";
      for (const auto &r : names.regions)
        AssertThrow(r != "All", ExcMessage("Discretization/Regions/Names: 'All' is predefined; choose another name"));
    }
    // Pass 2: the model of each material and damage model.
    {
      ParameterHandler prm;
      declare_parameters(prm, names);
      parse_input_file(prm, file, false);
      for (auto &[section, map] : std::vector<std::pair<std::string, std::map<std::string, std::string> *>>{
             {"Materials", &names.materials}, {"Damage models", &names.damage_models}})
        {
          prm.enter_subsection(section);
          for (auto &entry : *map)
            {
              prm.enter_subsection(entry.first);
              entry.second = Utilities::trim(prm.get("Model"));
              AssertThrow(!entry.second.empty(),
                          ExcMessage(section + "/" + entry.first + "/Model is not set"));
              prm.leave_subsection();
            }
          prm.leave_subsection();
        }
      for (const auto &[name, model] : names.materials)
        Registry<Material>::instance().get(model, "Materials/" + name + "/Model");
      for (const auto &[name, model] : names.damage_models)
        Registry<DamageModel>::instance().get(model, "Damage models/" + name + "/Model");
    }
    // Pass 3: everything, strictly.
    ParameterHandler prm;
    declare_parameters(prm, names);
    parse_input_file(prm, file, true);
    output.keep_parameters(prm); // written with the output: the run's full parameter set

    prm.enter_subsection("Discretization");
    scene.parse_parameters(prm);
    prm.enter_subsection("Regions");
    for (const auto &name : names.regions)
      {
        prm.enter_subsection(name);
        auto region  = std::make_unique<Region>();
        region->name = name;
        region->parse_parameters(prm, "Discretization/Regions/" + name);
        regions[name] = std::move(region);
        prm.leave_subsection();
      }
    prm.leave_subsection();
    prm.enter_subsection("Bond filters");
    for (const auto &name : names.bond_filters)
      {
        prm.enter_subsection(name);
        bond_filters.emplace_back();
        bond_filters.back().name = name;
        bond_filters.back().parse_parameters(prm, "Discretization/Bond filters/" + name);
        prm.leave_subsection();
      }
    prm.leave_subsection();
    prm.leave_subsection();

    AssertThrow(!names.blocks.empty(),
                ExcMessage("Blocks/Names is empty: define at least one block"));
    prm.enter_subsection("Blocks");
    for (const auto &name : names.blocks)
      {
        const std::string path = "Blocks/" + name;
        prm.enter_subsection(name);
        Block block;
        block.name          = name;
        block.material_name = Utilities::trim(prm.get("Material"));
        block.damage_name   = Utilities::trim(prm.get("Damage model"));
        block.region        = Utilities::trim(prm.get("Region"));
        block.horizon       = prm.get_double("Horizon");
        block.continuum     = prm.get("Type") == "Continuum";
        block.fe_degree     = prm.get_integer("FE degree");
        for (const int id : Utilities::string_to_int(Utilities::split_string_list(prm.get("Material ids"), ',')))
          block.material_ids.push_back(id);
        prm.leave_subsection();

        AssertThrow(!block.material_name.empty(), ExcMessage(path + "/Material is not set"));
        AssertThrow(names.materials.count(block.material_name),
                    ExcMessage(path + "/Material: '" + block.material_name +
                               "' is not defined in Materials/Names"));
        AssertThrow(block.damage_name.empty() || names.damage_models.count(block.damage_name),
                    ExcMessage(path + "/Damage model: '" + block.damage_name +
                               "' is not defined in Damage models/Names"));
        AssertThrow(!block.continuum || block.damage_name.empty(),
                    ExcMessage(path + "/Damage model: a continuum block does not break; remove the damage "
                                      "model or make the block Peridynamic"));
        AssertThrow(block.region.empty() || block.region == "All" || regions.count(block.region),
                    ExcMessage(path + "/Region: '" + block.region +
                               "' is not defined in Discretization/Regions/Names"));
        if (block.horizon == 0)
          block.horizon = scene.horizon;
        AssertThrow(block.horizon > 0,
                    ExcMessage(path + "/Horizon and Discretization/Horizon are both 0: "
                                      "set a positive horizon"));
        blocks.push_back(std::move(block));
      }
    prm.leave_subsection();

    // One material (and damage model) instance per block: the horizon differs.
    for (auto &block : blocks)
      {
        const std::string model = names.materials.at(block.material_name);
        prm.enter_subsection("Materials");
        prm.enter_subsection(block.material_name);
        block.material = Registry<Material>::instance().get(model, "").create();
        block.material->parse_parameters(prm, "Materials/" + block.material_name);
        prm.leave_subsection();
        prm.leave_subsection();
        if (!block.damage_name.empty())
          {
            prm.enter_subsection("Damage models");
            prm.enter_subsection(block.damage_name);
            block.damage = Registry<DamageModel>::instance()
                             .get(names.damage_models.at(block.damage_name), "")
                             .create();
            block.damage->parse_parameters(prm, "Damage models/" + block.damage_name);
            prm.leave_subsection();
            prm.leave_subsection();
          }
      }
    for (auto &block : blocks)
      if (block.continuum)
        {
          has_continuum = true;
          block.elasticity = std::make_unique<LinearElasticity>(block.material->bulk_modulus(),
                                                                block.material->shear_modulus(),
                                                                block.material->density());
        }
    // Materials declared but not used are still parsed, so their errors show.
    prm.enter_subsection("Materials");
    for (const auto &[name, model] : names.materials)
      {
        prm.enter_subsection(name);
        Registry<Material>::instance().get(model, "").create()->parse_parameters(prm, "Materials/" + name);
        prm.leave_subsection();
      }
    prm.leave_subsection();

    const auto require_region = [&](const std::string &path, const std::string &region) {
      AssertThrow(region == "All" || regions.count(region),
                  ExcMessage(path + "/Region: '" + region + "' is not defined in Discretization/Regions/Names"));
    };
    prm.enter_subsection("Coupling");
    blending_width       = prm.get_double("Blending width");
    const std::string levels = prm.get("Virtual point levels");
    virtual_point_levels     = levels == "auto" ? -1 : std::stoi(levels);
    prm.leave_subsection();

    prm.enter_subsection("Boundary conditions");
    for (const auto &name : names.conditions)
      {
        const std::string path = "Boundary conditions/" + name;
        prm.enter_subsection(name);
        BoundaryCondition bc;
        bc.name = name;
        bc.parse_parameters(prm, path);
        require_region(path, bc.region);
        conditions.push_back(std::move(bc));
        prm.leave_subsection();
      }
    prm.leave_subsection();

    prm.enter_subsection("Computes");
    for (const auto &name : names.computes)
      {
        const std::string path = "Computes/" + name;
        prm.enter_subsection(name);
        RegionCompute compute;
        compute.name = name;
        compute.parse_parameters(prm, path);
        require_region(path, compute.region);
        computes.push_back(std::move(compute));
        prm.leave_subsection();
      }
    prm.leave_subsection();

    prm.enter_subsection("Solver");
    solver_type         = prm.get("Type");
    prm.enter_subsection("Implicit");
    implicit.parse_parameters(prm);
    prm.leave_subsection();
    initial_time        = prm.get_double("Initial time");
    final_time          = prm.get_double("Final time");
    requested_steps     = prm.get_integer("Number of steps");
    energy_growth_limit = prm.get_double("Energy growth limit");
    track_dissipation   = prm.get_bool("Track dissipated energy");
    prm.enter_subsection("Verlet");
    fixed_dt      = prm.get_double("Fixed dt");
    safety_factor = prm.get_double("Safety factor");
    prm.leave_subsection();
    prm.leave_subsection();
    AssertThrow(solver_type != "QuasiStatic" || requested_steps > 0,
                ExcMessage("Solver/Number of steps: the quasistatic solver needs the number of load steps (> 0)"));
    AssertThrow(solver_type != "Newmark" || (requested_steps > 0 && final_time > initial_time),
                ExcMessage("Solver/Number of steps and Final time: the Newmark solver takes Number of steps "
                           "equal steps from Initial time to Final time; set both"));
    AssertThrow(requested_steps > 0 || final_time > initial_time,
                ExcMessage("Solver/Final time must be after Solver/Initial time (or set "
                           "Solver/Number of steps)"));
    AssertThrow(!has_continuum || solver_type == "Verlet" || implicit.jacobian == "Assembled",
                ExcMessage("Solver/Implicit/Jacobian: a scene with continuum blocks needs Assembled (the FE "
                           "stiffness joins the PD tangent in one matrix)"));
    AssertThrow(fixed_dt > 0 || safety_factor > 0,
                ExcMessage("Solver/Verlet/Safety factor must be positive when Fixed dt is 0"));

    prm.enter_subsection("Output");
    output.parse_parameters(prm);
    prm.leave_subsection();
  }

  // -------------------------------------------------------------------- set-up

  void
  Simulation::check_region_expressions() const
  {
    std::vector<const Expression *> expressions;
    for (const auto &[name, region] : regions)
      expressions.push_back(region->user_expression());
    check_finite(expressions, comm);
  }

  int
  Simulation::block_of_cell(const CellIterator &cell) const
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
  Simulation::check_blocks_have_cells() const
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
  Simulation::setup()
  {
    const auto start = std::chrono::steady_clock::now();
    {
      TimerOutput::Scope t(timer, "setup: mesh and points");
      // The size before allocating it (size_check.cc): a built-in scene from
      // its parameters, a Gmsh mesh once read (bounded by the file's size).
      const AvailableMemory available = available_memory(comm);
      report_p4est_out_of_memory();
      check_scene_size(available);
      scene.create_triangulation(triangulation);
      if (scene.type == "Gmsh")
        check_mesh_size(available, "the mesh", "Discretization/Gmsh/Mesh file");
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
              // A cell's weight: its bonds plus a few for the per-point work
              // (time integration, ghost exchange); cells without a point: 1.
              for (const auto &cell : triangulation.active_cell_iterators())
                if (cell->is_locally_owned())
                  cell->set_user_index(1);
              for (unsigned int i = 0; i < cloud.n_owned(); ++i)
                {
                  const unsigned int weight = bonds.offsets[i + 1] - bonds.offsets[i] + 4;
                  // Virtual points share their FE cell.
                  cloud.cell[i]->set_user_index(is_virtual(i) ? cloud.cell[i]->user_index() + weight : weight);
                }
              const auto connection = triangulation.signals.weight.connect(
                [](const Triangulation<dim>::cell_iterator &cell, const Triangulation<dim>::CellStatus) -> unsigned int {
                  return cell->user_index();
                });
              triangulation.repartition();
              connection.disconnect();
            }
            unbalanced_bonds = 100 * (balance.max / balance.avg - 1);
            build_points_and_bonds();
          }
      }
    setup_models();
    setup_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  void
  Simulation::build_points_and_bonds()
  {
    {
      TimerOutput::Scope t(timer, "setup: mesh and points");

      const auto block_of = [this](const CellIterator &cell) { return block_of_cell(cell); };
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            const int b = block_of(cell);
            cell->set_active_fe_index(b >= 0 && blocks[b].continuum ? blocks[b].fe_degree : 0);
          }
      dof_handler.distribute_dofs(fe);

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
      check_blocks_have_cells();
      unsigned int bad_volume = 0;
      for (unsigned int i = 0; i < cloud.n_owned(); ++i)
        if (!(cloud.volume[i] > 0))
          ++bad_volume;
      bad_volume = Utilities::MPI::sum(bad_volume, comm);
      AssertThrow(bad_volume == 0,
                  ExcMessage(std::to_string(bad_volume) + " cells have zero or negative volume: "
                             "the mesh is degenerate or inverted"));
    }
    {
      TimerOutput::Scope        t(timer, "setup: neighbor search");
      std::vector<double>       horizon(blocks.size());
      for (unsigned int b = 0; b < blocks.size(); ++b)
        horizon[b] = blocks[b].horizon;
      bonds = find_families(cloud, horizon, comm, cloud.max_cell_radius);
      if (scene.partial_volumes)
        {
          compute_partial_volumes(cloud, bonds, horizon);
          cloud.cell_vertices = std::vector<double>(); // set-up only
        }
      if (!bond_filters.empty())
        apply_bond_filters();
      if (has_continuum)
        drop_unweighted_bonds();
    }
  }

  void
  Simulation::apply_bond_filters()
  {
    filtered_bonds.assign(bond_filters.size(), 0);
    const bool periodic = cloud.periodicity.any();
    bonds.keep_if(cloud.n_owned(), [&](const unsigned int i, const unsigned int j) {
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
  Simulation::setup_models()
  {
    // A point without a neighbor cannot carry load: a horizon below the spacing.
    {
      unsigned int isolated = 0;
      BestPoint    first(BestPoint::Order::smallest); // the smallest global id
      for (unsigned int i = 0; i < cloud.n_owned(); ++i)
        if (bonds.offsets[i + 1] == bonds.offsets[i] && !is_virtual(i)) // see drop_unweighted_bonds()
          {
            ++isolated;
            first.consider(0, cloud.gid[i], &cloud.X[3 * i], BestPoint::Kind::point, cloud.block[i]);
          }
      const unsigned int total = Utilities::MPI::sum(isolated, comm);
      if (total > 0)
        {
          const BestPoint p     = first.global(comm);
          const Block    &block = blocks[static_cast<unsigned int>(p.tag)];
          AssertThrow(false,
                      ExcMessage(std::to_string(total) + " points have no neighbor within the horizon, "
                                 "the first " + p.describe() +
                                 " in block '" + block.name + "' with horizon " + sci(block.horizon) +
                                 ": the horizon must exceed the point spacing (Blocks/" + block.name +
                                 "/Horizon or Discretization/Horizon)"));
        }
    }

    for (auto &block : blocks)
      block.points.clear();
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      blocks[cloud.block[i]].points.push_back(i);

    // Bonds between blocks of different models cannot be evaluated by either.
    {
      std::vector<std::string> model(blocks.size());
      for (unsigned int b = 0; b < blocks.size(); ++b)
        model[b] = typeid(*blocks[b].material).name();
      bool mixed = false, mixed_damage = false;
      std::pair<unsigned int, unsigned int> pair{0, 0};
      for (unsigned int i = 0; i < cloud.n_owned(); ++i)
        for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
          {
            const unsigned int bi = cloud.block[i], bj = cloud.block[bonds.neighbor[b]];
            if (bi != bj && model[bi] != model[bj])
              mixed = true, pair = {bi, bj};
            if (bi != bj && blocks[bi].damage_name != blocks[bj].damage_name)
              mixed_damage = true;
          }
      const unsigned int any = Utilities::MPI::max(mixed ? 1u : 0u, comm);
      AssertThrow(any == 0,
                  ExcMessage("blocks '" + blocks[pair.first].name + "' and '" + blocks[pair.second].name +
                             "' (or others) are within a horizon of each other but use different "
                             "material models; bonds between models are not defined: use the same "
                             "model with different parameters, or separate the blocks by more than "
                             "a horizon"));
      if (Utilities::MPI::max(mixed_damage ? 1u : 0u, comm))
        warnings.push_back("bonds join blocks with different damage models; each half of such a "
                           "bond is decided by its own block's model");
    }

    bool any_damage = false;
    for (const auto &b : blocks)
      any_damage |= b.damage != nullptr;
    if (any_damage)
      broken.assign(bonds.n_bonds(), 0);

    fields = std::make_unique<FieldStore>(cloud);
    displacement.reinit(cloud.vector_partitioner);
    velocity.reinit(cloud.vector_partitioner);
    force.reinit(cloud.vector_partitioner);
    mass_density.resize(cloud.n_owned());
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      mass_density[i] = is_virtual(i) ? 0.0 : blocks[cloud.block[i]].material->density(); // virtual: no mass of their own

    ModelState state{cloud, bonds, nullptr, displacement.begin(), force.begin(), nullptr, *fields};
    std::set<std::string> constant, stage;
    fused_breaking.clear();
    for (unsigned int b = 0; b < blocks.size(); ++b)
      {
        blocks[b].material->set_block(b, blocks[b].horizon);
        blocks[b].material->initialize(state, blocks[b].points);
        if (blocks[b].continuum)
          AssertThrow(blocks[b].material->weight_energy(state, blocks[b].points, point_alpha.data()),
                      ExcMessage("Blocks/" + blocks[b].name + "/Type: material '" + blocks[b].material_name +
                                 "' cannot weight its energy, so it cannot be coupled to a continuum block"));
        if (blocks[b].damage)
          blocks[b].damage->initialize(*blocks[b].material, blocks[b].horizon);
        fused_breaking.emplace_back();
        if (blocks[b].damage && blocks[b].damage->critical_stretch() > 0 &&
            blocks[b].material->fuses_stretch_criterion())
          {
            fused_breaking.back().squared_limit =
              stretch_squared_limit(blocks[b].damage->critical_stretch());
            fused_breaking.back().broken = broken.data();
          }
        for (const auto &f : blocks[b].material->constant_fields())
          constant.insert(f);
        for (const auto &f : blocks[b].material->stage_fields())
          stage.insert(f);
      }
    for (const auto &f : constant)
      fields->get(f).update_ghost_values();
    for (const auto &f : stage)
      fields->get(f); // allocate before the loop: no allocation per step
    ghosted_stage_fields.assign(stage.begin(), stage.end());

    if (has_continuum)
      {
        TimerOutput::Scope t(timer, "setup: continuum");
        setup_continuum();
      }

    // Conditions: their points, the constraints, the body force.
    for (auto &bc : conditions)
      {
        bc.faces.clear();
        if (bc.type == BoundaryCondition::Type::traction)
          {
            AssertThrow(has_continuum,
                        ExcMessage("Boundary conditions/" + bc.name + "/Type: a Traction acts on the boundary faces "
                                   "of continuum blocks, and this scene has none; load peridynamic blocks with "
                                   "a Body force"));
            bc.points.clear();
            bc.nodes.clear();
            for (const auto &cell : dof_handler.active_cell_iterators())
              if (cell->is_locally_owned() && cell->active_fe_index() > 0)
                for (const unsigned int f : cell->face_indices())
                  if (cell->face(f)->at_boundary() &&
                      (bc.boundary_id >= 0 ? cell->face(f)->boundary_id() == types::boundary_id(bc.boundary_id) :
                                             in_region(bc.region, cell->face(f)->center(), cell)))
                    bc.faces.emplace_back(cell, f);
            if (Utilities::MPI::sum(bc.faces.size(), comm) == 0)
              warnings.push_back("traction '" + bc.name + "' acts on no boundary face of a continuum block");
            continue;
          }
        bc.points.clear();
        for (unsigned int i = 0; i < cloud.n_owned(); ++i)
          if (!is_virtual(i) && in_region(bc.region, cloud.position(i), cloud.cell[i]))
            bc.points.push_back(i);
        bc.nodes.clear();
        if (has_continuum)
          for (unsigned int k = 0; k < continuum->nodes.size(); ++k)
            {
              const auto &node = continuum->nodes[k];
              if (node.component == bc.component && in_region(bc.region, node.x, node.cell))
                bc.nodes.push_back(k);
            }
        if (Utilities::MPI::sum(bc.points.size() + bc.nodes.size(), comm) == 0)
          warnings.push_back("boundary condition '" + bc.name + "' acts on no point (region '" +
                             bc.region + "' is empty)");
      }
    for (auto &compute : computes)
      {
        compute.points.clear();
        for (unsigned int i = 0; i < cloud.n_owned(); ++i)
          if (!is_virtual(i) && in_region(compute.region, cloud.position(i), cloud.cell[i]))
            compute.points.push_back(i);
        compute.nodes.clear();
        if (has_continuum)
          for (unsigned int k = 0; k < continuum->nodes.size(); ++k)
            {
              const auto &node = continuum->nodes[k];
              if (compute.uses_node(node.component) && in_region(compute.region, node.x, node.cell))
                compute.nodes.push_back(k);
            }
        // Over nothing, a Minimum is +1.8e308, a Mean 0: numbers that look
        // like results. A compute over an empty region is a mistake.
        AssertThrow(Utilities::MPI::sum(compute.points.size() + compute.nodes.size(), comm) > 0,
                    ExcMessage("Computes/" + compute.name + "/Region: the region '" + compute.region +
                               "' holds no point" + (has_continuum ? " or FE node" : "") +
                               " of the body, so '" + compute.operation + "' of " + compute.variable +
                               " over it has no value: check Discretization/Regions/" + compute.region +
                               " against the mesh's extent"));
      }
    check_region_expressions();
    // Two conditions of the same kind on the same component of a point: the
    // later one silently replaced the earlier there. Say so.
    for (unsigned int a = 0; a < conditions.size(); ++a)
      for (unsigned int b = a + 1; b < conditions.size(); ++b)
        {
          const auto &ca = conditions[a], &cb = conditions[b];
          const bool  same_kind = ca.is_prescribed() ? cb.is_prescribed() : ca.is_initial() && ca.type == cb.type;
          if (!same_kind || ca.component != cb.component)
            continue;
          const auto common = [](const std::vector<unsigned int> &x, const std::vector<unsigned int> &y) {
            std::vector<unsigned int> sx(x), sy(y), both;
            std::sort(sx.begin(), sx.end());
            std::sort(sy.begin(), sy.end());
            std::set_intersection(sx.begin(), sx.end(), sy.begin(), sy.end(), std::back_inserter(both));
            return both.size();
          };
          const auto n = Utilities::MPI::sum(common(ca.points, cb.points) + common(ca.nodes, cb.nodes), comm);
          if (n > 0)
            warnings.push_back("boundary conditions '" + ca.name + "' and '" + cb.name + "' both " +
                               (ca.is_prescribed() ? "prescribe" : "set the initial value of") + " component " +
                               std::string(1, char('x' + ca.component)) + " at " + std::to_string(n) +
                               " points; there the later one in Boundary conditions/Names ('" + cb.name +
                               "') replaces '" + ca.name + "': make their regions disjoint if that is not meant");
        }
    constraints.clear();
    {
      // A later condition on the same component of the same point wins.
      std::map<std::pair<unsigned int, unsigned int>, unsigned int> owner;
      for (unsigned int c = 0; c < conditions.size(); ++c)
        if (conditions[c].is_prescribed())
          for (const unsigned int i : conditions[c].points)
            owner[{i, conditions[c].component}] = c;
      for (const auto &[key, c] : owner)
        constraints.push_back({key.first, key.second, c});
      constraint_force.assign(constraints.size(), 0.0);
    }
    node_constraints.clear();
    if (has_continuum)
      {
        std::map<unsigned int, unsigned int> owner;
        for (unsigned int c = 0; c < conditions.size(); ++c)
          if (conditions[c].is_prescribed())
            for (const unsigned int k : conditions[c].nodes)
              owner[k] = c;
        for (const auto &[k, c] : owner)
          node_constraints.push_back({k, c});
        node_constraint_force.assign(node_constraints.size(), 0.0);
      }
    body_force.clear();
    loads_depend_on_time = false;
    for (const auto &bc : conditions)
      if (bc.is_load())
        {
          if (bc.type == BoundaryCondition::Type::body_force)
            body_force.resize(dim * cloud.n_owned(), 0.0);
          loads_depend_on_time |= bc.value->depends_on_time();
          if (has_continuum && continuum->load.size() == 0)
            continuum->load.reinit(continuum->F);
        }

    dt_stable = stable_time_step();
    dt        = fixed_dt > 0 ? fixed_dt : safety_factor * dt_stable;
    if (fixed_dt > dt_stable)
      warnings.push_back("Fixed dt " + sci(fixed_dt) + " exceeds the stable estimate " +
                         sci(dt_stable) + " (" + sci(fixed_dt / dt_stable, 3) +
                         " times): the run may become unstable");

  }

  double
  Simulation::stable_time_step()
  {
    ModelState state{cloud, bonds, nullptr, displacement.begin(), force.begin(), nullptr, *fields};
    double     local = std::numeric_limits<double>::max();
    // Constants each within double's range can still overflow in the force
    // law (K / horizon^4, sqrt(K / rho)): refuse them here, naming them,
    // before they surface as a blow-up blamed on the loading.
    std::vector<unsigned int> bad(blocks.size(), 0);
    for (unsigned int k = 0; k < blocks.size(); ++k)
      {
        const Block &b = blocks[k];
        if (!b.points.empty() && !b.continuum) // virtual points carry no mass: the FE nodes do
          {
            const double dt_block = b.material->stable_time_step(state, b.points);
            // The largest double: no point of the block has any stiffness.
            bad[k] = !(dt_block > 0 && dt_block < std::numeric_limits<double>::max());
            local                 = std::min(local, dt_block);
          }
      }
    Utilities::MPI::max(bad, comm, bad);
    const double fe = has_continuum ? continuum->stable_time_step() : std::numeric_limits<double>::max();
    for (unsigned int k = 0; k < blocks.size(); ++k)
      {
        const Block &b = blocks[k];
        AssertThrow(!bad[k] && (!b.continuum || (fe > 0 && fe < std::numeric_limits<double>::max())),
                    ExcMessage("Materials/" + b.material_name + ": in block '" + b.name + "' (horizon " +
                               sci(b.horizon) + ") its constants (Bulk modulus " + sci(b.material->bulk_modulus()) +
                               ", Shear modulus " + sci(b.material->shear_modulus()) + ", Density " +
                               sci(b.material->density()) + ") give no finite stable time step: the force law " +
                               "leaves the range of double (the micromodulus is about 18 K / (pi horizon^4)). " +
                               "Give the constants and lengths in units that keep them nearer to 1 (e.g. MPa, mm)"));
      }
    const double pd = Utilities::MPI::min(local, comm);
    return has_continuum ? std::min(pd, fe) : pd;
  }

  // ------------------------------------------------------------------- physics

  void
  Simulation::compute_forces(const bool with_energy)
  {
    const unsigned int n = cloud.n_owned();
    std::fill(force.begin(), force.begin() + dim * n, 0.0);
    if (with_energy)
      energy_density.assign(n, 0.0);
    ModelState state{cloud,
                     bonds,
                     broken.empty() ? nullptr : broken.data(),
                     displacement.begin(),
                     force.begin(),
                     with_energy ? energy_density.data() : nullptr,
                     *fields};
    // A block whose material applies its critical stretch in its own first
    // bond pass (fused_breaking) gets it there; other damage models run their
    // own pass first.
    const auto block_state = [&](const unsigned int k) {
      ModelState s = state;
      s.breaking   = breaking_allowed && fused_breaking[k].squared_limit > 0 ? &fused_breaking[k] : nullptr;
      return s;
    };
    if (!broken.empty() && breaking_allowed)
      {
        TimerOutput::Scope t(timer, "damage");
        for (unsigned int k = 0; k < blocks.size(); ++k)
          if (blocks[k].damage && fused_breaking[k].squared_limit == 0)
            broken_bond_count += blocks[k].damage->update(state, blocks[k].points, broken.data());
      }
    {
      TimerOutput::Scope t(timer, "force");
      for (unsigned int k = 0; k < blocks.size(); ++k)
        blocks[k].material->compute_stage(block_state(k), blocks[k].points);
    }
    if (!ghosted_stage_fields.empty())
      {
        TimerOutput::Scope t(timer, "ghost exchange");
        for (const auto &f : ghosted_stage_fields)
          fields->get(f).update_ghost_values();
      }
    {
      TimerOutput::Scope t(timer, "force");
      for (unsigned int k = 0; k < blocks.size(); ++k)
        blocks[k].material->compute_force(block_state(k), blocks[k].points);
    }
    for (auto &b : fused_breaking)
      {
        broken_bond_count += b.newly_broken;
        b.newly_broken = 0;
      }
    if (!body_force.empty())
      for (unsigned int k = 0; k < dim * n; ++k)
        force.local_element(k) += body_force[k];
    if (has_continuum)
      {
        // The virtual points' forces go to the FE nodes (Pi^T), action = reaction.
        TimerOutput::Scope t(timer, "continuum");
        for (unsigned int k = 0; k < virtual_points.size(); ++k)
          for (unsigned int d = 0; d < dim; ++d)
            f_virtual[dim * k + d] =
              cloud.volume[virtual_points[k]] * force.local_element(dim * virtual_points[k] + d);
        continuum->compute_force(f_virtual);
      }
  }

  void
  Simulation::apply_initial_conditions()
  {
    displacement = 0;
    velocity     = 0;
    for (const auto &bc : conditions)
      if (bc.is_initial() || bc.is_prescribed())
        {
          VectorType &target = (bc.type == BoundaryCondition::Type::initial_velocity ||
                                bc.type == BoundaryCondition::Type::prescribed_velocity) ?
                                 velocity :
                                 displacement;
          for (const unsigned int i : bc.points)
            target.local_element(dim * i + bc.component) =
              bc.value->value(cloud.position(i), initial_time, cloud.hash(i));
          if (has_continuum)
            {
              ContinuumField::VectorType &fe_target = &target == &velocity ? continuum->V : continuum->U;
              for (const unsigned int k : bc.nodes)
                fe_target.local_element(continuum->nodes[k].local) =
                  bc.value->value(continuum->nodes[k].x, initial_time, 0);
            }
        }
    if (has_continuum && continuum->hanging.n_constraints() > 0)
      {
        continuum->hanging.distribute(continuum->U);
        continuum->hanging.distribute(continuum->V);
      }
    // Where the prescribed velocities start from (apply_prescribed).
    constraint_displacement.resize(constraints.size());
    for (unsigned int k = 0; k < constraints.size(); ++k)
      constraint_displacement[k] = displacement.local_element(dim * constraints[k].point + constraints[k].component);
    node_constraint_displacement.resize(node_constraints.size());
    for (unsigned int k = 0; k < node_constraints.size(); ++k)
      node_constraint_displacement[k] = continuum->U.local_element(continuum->nodes[node_constraints[k].node].local);
    evaluate_loads(initial_time);
    check_condition_values(first_nonfinite_condition(initial_time), initial_time);
  }

  void
  Simulation::evaluate_loads(const double time)
  {
    const bool fe_loads = has_continuum && continuum->load.size() > 0;
    if (body_force.empty() && !fe_loads)
      return;
    std::fill(body_force.begin(), body_force.end(), 0.0);
    if (fe_loads)
      continuum->load = 0;
    for (const auto &bc : conditions)
      if (bc.type == BoundaryCondition::Type::traction)
        continuum->add_face_load(bc.faces, bc.component,
                                 [&](const Point<dim> &x) { return bc.value->value(x, time, 0); });
      else if (bc.type == BoundaryCondition::Type::body_force)
        {
          for (const unsigned int i : bc.points)
            body_force[dim * i + bc.component] += bc.value->value(cloud.position(i), time, cloud.hash(i));
          // FE nodes: b(x_a) int N_a, i.e. the lumped mass over the density
          // (exact for a constant b).
          for (const unsigned int k : bc.nodes)
            {
              const auto &node = continuum->nodes[k];
              continuum->load.local_element(node.local) +=
                bc.value->value(node.x, time, 0) * continuum->mass.local_element(node.local) / node_density[k];
            }
        }
    if (fe_loads)
      continuum->load.compress(VectorOperation::add);
  }

  unsigned int
  Simulation::first_nonfinite_condition(const double time) const
  {
    for (unsigned int c = 0; c < conditions.size(); ++c)
      for (const unsigned int i : conditions[c].points)
        if (!std::isfinite(conditions[c].value->value(cloud.position(i), time, cloud.hash(i))))
          return c + 1;
    return 0;
  }

  void
  Simulation::check_condition_values(const unsigned int bad_local, const double time) const
  {
    // Collective: the offending point may live on one rank only.
    const unsigned int bad = Utilities::MPI::max(bad_local, comm);
    if (bad == 0)
      return;
    // The expressions remember where they first failed: name that point.
    std::vector<const Expression *> values;
    for (const auto &bc : conditions)
      values.push_back(bc.value.get());
    check_finite(values, comm);
    AssertThrow(false,
                ExcMessage("Boundary conditions/" + conditions[bad - 1].name + "/Value: '" +
                           conditions[bad - 1].value->text() + "' is not finite at some of its points at t = " +
                           sci(time, 6)));
  }

  void
  Simulation::apply_prescribed(const double time, const double step_dt)
  {
    // One prescribed entry (u, v) at x for the step that ends at time. A
    // prescribed velocity integrates its own displacement (midpoint rule) in
    // @p own and assigns it: the integrators may have moved u already (the
    // Verlet drift, Newmark's predictor), which must not count twice.
    const auto prescribe = [&](const unsigned int condition, const Point<dim> &x, const std::uint64_t h, double &u,
                               double &v, double &own) {
      const BoundaryCondition &bc = conditions[condition];
      if (bc.type == BoundaryCondition::Type::prescribed_displacement)
        {
          const double now = bc.value->value(x, time, h);
          v                = (now - bc.value->value(x, time - step_dt, h)) / step_dt;
          u                = now;
        }
      else
        {
          own += step_dt * bc.value->value(x, time - 0.5 * step_dt, h);
          u = own;
          v = bc.value->value(x, time, h);
        }
      if (!std::isfinite(u) || !std::isfinite(v))
        bad_condition = condition + 1;
    };
    for (unsigned int k = 0; k < constraints.size(); ++k)
      {
        const Constraint  &c = constraints[k];
        const unsigned int e = dim * c.point + c.component;
        prescribe(c.condition, cloud.position(c.point), cloud.hash(c.point), displacement.local_element(e),
                  velocity.local_element(e), constraint_displacement[k]);
      }
    for (unsigned int k = 0; k < node_constraints.size(); ++k)
      {
        const ContinuumField::Node &node = continuum->nodes[node_constraints[k].node];
        prescribe(node_constraints[k].condition, node.x, 0, continuum->U.local_element(node.local),
                  continuum->V.local_element(node.local), node_constraint_displacement[k]);
      }
  }

  // -------------------------------------------------------------------- output

  std::vector<std::pair<std::string, double>>
  Simulation::global_quantities(const unsigned int step, const double time)
  {
    const unsigned int n  = cloud.n_owned();
    double             ke = 0, se = 0, max_damage = 0;
    for (unsigned int i = 0; i < n; ++i)
      {
        const double *v = velocity.begin() + dim * i;
        ke += 0.5 * mass_density[i] * cloud.volume[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        se += energy_density[i] * cloud.volume[i];
      }
    std::size_t broken_local = 0;
    if (!broken.empty())
      for (unsigned int i = 0; i < n; ++i)
        {
          for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
            broken_local += broken[b];
          max_damage = std::max(max_damage, point_damage(i));
        }
    ke                  = Utilities::MPI::sum(ke, comm);
    se                  = Utilities::MPI::sum(se, comm);
    if (has_continuum)
      {
        ke += continuum->kinetic_energy();
        se += continuum->strain_energy();
      }
    last_kinetic_energy = ke;
    last_strain_energy  = se;
    max_damage         = Utilities::MPI::max(max_damage, comm);
    const double broken_bonds = Utilities::MPI::sum(double(broken_local), comm) / 2;
    std::vector<std::pair<std::string, double>> row{{"step", step},
                                                    {"time", time},
                                                    {"kinetic_energy", ke},
                                                    {"strain_energy", se},
                                                    {"external_work", external_work},
                                                    {"broken_bonds", broken_bonds},
                                                    {"max_damage", max_damage}};
    for (const auto &compute : computes)
      {
        const std::function<double(unsigned int)> value =
          compute.variable == "Damage" ? std::function<double(unsigned int)>([this](unsigned int i) { return point_damage(i); }) :
          compute.variable == "Bond stretch" ? std::function<double(unsigned int)>([this](unsigned int i) { return point_stretch(i); }) :
          compute.variable[0] == 'D' ?
            std::function<double(unsigned int)>([this, &compute](unsigned int i) {
              return displacement.local_element(dim * i + compute.component);
            }) :
          compute.variable == "Kinetic energy" ?
            std::function<double(unsigned int)>([this](unsigned int i) {
              const double *v = velocity.begin() + dim * i;
              return 0.5 * mass_density[i] * cloud.volume[i] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            }) :
          compute.variable[0] == 'P' ?
            std::function<double(unsigned int)>([this, &compute](unsigned int i) {
              return cloud.X[dim * i + compute.component];
            }) :
            std::function<double(unsigned int)>([this, &compute](unsigned int i) {
              return cloud.volume[i] * force.local_element(dim * i + compute.component);
            });
        std::function<double(unsigned int)> node_value, node_volume;
        if (has_continuum)
          {
            const auto local = [this](unsigned int k) { return continuum->nodes[k].local; };
            node_volume = [this, local](unsigned int k) { return continuum->mass.local_element(local(k)) / node_density[k]; };
            const char v = compute.variable[0];
            node_value =
              compute.variable == "Kinetic energy" ?
                std::function<double(unsigned int)>([this, local](unsigned int k) {
                  const double vk = continuum->V.local_element(local(k));
                  return 0.5 * continuum->mass.local_element(local(k)) * vk * vk;
                }) :
              v == 'D' ? std::function<double(unsigned int)>([this, local](unsigned int k) { return continuum->U.local_element(local(k)); }) :
              v == 'P' ? std::function<double(unsigned int)>([this](unsigned int k) { return continuum->nodes[k].x[continuum->nodes[k].component]; }) :
              v == 'F' ? std::function<double(unsigned int)>([this, local](unsigned int k) { return continuum->F.local_element(local(k)); }) :
                         std::function<double(unsigned int)>();
          }
        if (compute.reference)
          {
            const Expression &ref = *compute.reference;
            row.emplace_back(compute.name,
                             compute.evaluate([&](unsigned int i) { return std::abs(value(i) - ref.value(cloud.position(i), time)); },
                                              cloud.volume, comm,
                                              node_value ? std::function<double(unsigned int)>([&](unsigned int k) {
                                                return std::abs(node_value(k) - ref.value(continuum->nodes[k].x, time));
                                              }) :
                                                           std::function<double(unsigned int)>(),
                                              node_volume));
          }
        else
          row.emplace_back(compute.name, compute.evaluate(value, cloud.volume, comm, node_value, node_volume));
      }
    {
      // A Reference that is NaN somewhere would write nan in every row.
      std::vector<const Expression *> references;
      for (const auto &compute : computes)
        references.push_back(compute.reference.get());
      check_finite(references, comm);
    }
    if (solver_type != "Verlet")
      {
        row.emplace_back("newton_iterations", last_newton.newton_iterations);
        row.emplace_back("linear_iterations", last_newton.linear_iterations);
        row.emplace_back("damage_solves", last_damage_solves);
        row.emplace_back("residual", last_newton.residual);
        // The force each prescribed condition's supports put on the body.
        std::vector<double> reaction(conditions.size(), 0.0);
        for (const auto &c : constraints)
          reaction[c.condition] += support_force(c);
        for (const auto &c : node_constraints)
          reaction[c.condition] += node_support_force(c);
        Utilities::MPI::sum(reaction, comm, reaction);
        for (unsigned int c = 0; c < conditions.size(); ++c)
          if (conditions[c].is_prescribed())
            row.emplace_back("reaction_" + conditions[c].name, reaction[c]);
      }
    return row;
  }

  void
  Simulation::write_output(const unsigned int step, const double time, const bool globals, const bool field_files)
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

    const unsigned int n = cloud.n_owned();
    std::vector<std::unique_ptr<Vector<double>>> cell_storage;
    std::vector<OutputWriter::CellField>         cell_fields;
    auto cell_field = [&](const std::string &name, const std::function<double(unsigned int)> &value) {
      if (!output.wants(name))
        return;
      cell_storage.push_back(std::make_unique<Vector<double>>(triangulation.n_active_cells()));
      for (unsigned int i = 0; i < n; ++i)
        if (!is_virtual(i))
          (*cell_storage.back())[cloud.cell[i]->active_cell_index()] = value(i);
      cell_fields.emplace_back(name, cell_storage.back().get());
    };
    cell_field("Damage", [&](unsigned int i) { return point_damage(i); });
    auto field_or_zero = [&](const std::string &field) {
      return [this, field](unsigned int i) {
        return fields->has(field) ? fields->get(field).local_element(i) : 0.0;
      };
    };
    cell_field("Dilatation", field_or_zero("dilatation"));
    cell_field("Weighted volume", field_or_zero("weighted_volume"));
    cell_field("Number of neighbors", [&](unsigned int i) { return double(bonds.offsets[i + 1] - bonds.offsets[i]); });
    cell_field("Block", [&](unsigned int i) { return double(cloud.block[i]); });
    if (has_continuum && output.wants("Block"))
      for (unsigned int i = 0; i < n; ++i)
        if (is_virtual(i))
          (*cell_storage.back())[cloud.cell[i]->active_cell_index()] = cloud.block[i];
    const double rank = Utilities::MPI::this_mpi_process(comm);
    cell_field("Rank", [&](unsigned int) { return rank; });

    std::vector<std::unique_ptr<VectorType>> vector_storage;
    std::vector<OutputWriter::VectorField>   vector_fields;
    std::vector<types::global_dof_index>     dofs(dim);
    // On FE cells the nodal values (@p fe_value of a node), with the ghosts
    // the FE cells' output needs.
    IndexSet relevant;
    if (has_continuum)
      DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    auto vector_field = [&](const std::string                                 &name,
                            const std::function<double(unsigned int)>         &value,
                            const std::function<double(unsigned int)>         &fe_value) {
      if (!output.wants(name))
        return;
      vector_storage.push_back(has_continuum ?
                                 std::make_unique<VectorType>(dof_handler.locally_owned_dofs(), relevant, comm) :
                                 std::make_unique<VectorType>(dof_handler.locally_owned_dofs(), comm));
      VectorType &out = *vector_storage.back();
      for (unsigned int i = 0; i < n; ++i)
        if (!is_virtual(i))
          {
            cloud.cell[i]->get_dof_indices(dofs);
            for (unsigned int d = 0; d < dim; ++d)
              out(dofs[d]) = value(dim * i + d);
          }
      if (has_continuum)
        {
          for (unsigned int k = 0; k < continuum->nodes.size(); ++k)
            out.local_element(continuum->nodes[k].local) = fe_value(k);
          continuum->hanging.distribute(out);
          out.update_ghost_values();
        }
      vector_fields.emplace_back(name, &out);
    };
    // FE nodes: the force density and acceleration of the lumped system.
    const auto node_acceleration = [&](unsigned int k) {
      const unsigned int l = continuum->nodes[k].local;
      return continuum->mass.local_element(l) > 0 ? continuum->F.local_element(l) / continuum->mass.local_element(l) : 0.0;
    };
    vector_field("Displacement", [&](unsigned int k) { return displacement.local_element(k); },
                 [&](unsigned int k) { return continuum->U.local_element(continuum->nodes[k].local); });
    vector_field("Velocity", [&](unsigned int k) { return velocity.local_element(k); },
                 [&](unsigned int k) { return continuum->V.local_element(continuum->nodes[k].local); });
    vector_field("Force density", [&](unsigned int k) { return force.local_element(k); },
                 [&](unsigned int k) { return node_density[k] * node_acceleration(k); });
    vector_field("Acceleration", [&](unsigned int k) { return force.local_element(k) / mass_density[k / dim]; },
                 node_acceleration);

    output.write_fields(dof_handler, cell_fields, vector_fields, step, time, comm);
    if (globals)
      output.write_globals(row, comm);
  }

  // ---------------------------------------------------------------- reporting

  void
  Simulation::print_setup_report()
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
                              bonds.offsets.capacity() * sizeof(std::size_t) + broken.capacity() +
                              bonds.volume_fraction.capacity() * sizeof(float);
    const double point_bytes =
      cloud.X.capacity() * sizeof(double) + cloud.volume.capacity() * sizeof(double) +
      cloud.block.capacity() * sizeof(unsigned short) + cloud.key.capacity() * sizeof(PointKey) +
      cloud.gid.capacity() * sizeof(types::global_dof_index) + cloud.cell.capacity() * sizeof(CellIterator) +
      displacement.memory_consumption() + velocity.memory_consumption() + force.memory_consumption() +
      fields->memory_consumption() + mass_density.capacity() * sizeof(double);
    const double mesh_bytes = triangulation.memory_consumption() + dof_handler.memory_consumption();
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
    for (unsigned int f = 0; f < bond_filters.size(); ++f)
      pcout << "  bond filter '" << bond_filters[f].name << "': " << filtered_bonds[f] << " directed bonds cut"
            << (filtered_bonds[f] == 0 ? " (none: check its corner, vectors and lengths; the side runs along "
                                         "Normal x Bottom unit vector)" :
                                         "")
            << "\n";
    if (Utilities::MPI::n_mpi_processes(comm) > 1)
      {
        // The bond loops dominate a step: bonds per rank is the load balance.
        const auto minmax = Utilities::MPI::min_max_avg(double(bonds.n_bonds()), comm);
        pcout << "  bonds per rank:    " << std::setprecision(12) << minmax.min << " to " << minmax.max
              << " (the largest " << sci(100 * (minmax.max / minmax.avg - 1), 3) << "% above the mean";
        if (unbalanced_bonds > 0)
          pcout << "; " << sci(unbalanced_bonds, 3) << "% with equal cells per rank: repartitioned by bonds";
        pcout << ")\n";
      }
    for (const auto &b : blocks)
      if (b.continuum)
        pcout << "  block '" << b.name << "': continuum FE_Q(" << b.fe_degree << "), material '" << b.material_name
              << "' (E " << sci(b.elasticity->young_modulus()) << ", nu " << sci(b.elasticity->poisson_ratio(), 4)
              << "), " << Utilities::MPI::sum(b.points.size(), comm) << " virtual points\n";
      else
        pcout << "  block '" << b.name << "': " << Utilities::MPI::sum(b.points.size(), comm)
              << " points, material '" << b.material_name << "', horizon " << sci(b.horizon)
              << (b.damage ? ", damage: " + b.damage->describe() : std::string(", no damage")) << "\n";
    if (has_continuum)
      pcout << "  finite elements:   " << continuum->n_global_dofs << " DoFs (hanging-node constraints "
            << Utilities::MPI::sum(continuum->hanging.n_constraints(), comm) << "), blending band "
            << sci(blending_width, 3) << " horizons, virtual point levels "
            << (virtual_point_levels < 0 ? std::string("auto") : std::to_string(virtual_point_levels)) << "\n";
    for (const auto &bc : conditions)
      {
        // Collective on every rank.
        const auto nodes = Utilities::MPI::sum(bc.nodes.size(), comm), faces = Utilities::MPI::sum(bc.faces.size(), comm);
        const auto points = Utilities::MPI::sum(bc.points.size(), comm);
        pcout << "  condition '" << bc.name << "': "
              << (bc.type == BoundaryCondition::Type::traction ?
                    std::to_string(faces) + " boundary faces" :
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
    if (solver_type == "Verlet")
      pcout << "  stable time step:  " << sci(dt_stable, 6) << " (smallest over all points)\n"
            << "  time step:         " << sci(dt, 6)
            << (fixed_dt > 0 ? " (fixed)" : " (safety factor " + sci(safety_factor, 3) + ")") << "\n";
    for (const auto &w : warnings)
      pcout << "Warning: " << w << "\n";
    pcout << std::flush;
  }

  void
  Simulation::print_summary(const double loop_seconds, const unsigned int steps_done)
  {
    const double bonds_global = Utilities::MPI::sum(double(bonds.n_bonds()), comm);
    const double peak_sum     = peak_memory_bytes_sum(comm);
    const double peak_max     = Utilities::MPI::max(peak_memory_bytes(), comm);
    const double startup_sum  = Utilities::MPI::sum(startup_memory, comm);
    const double startup_max  = Utilities::MPI::max(startup_memory, comm);
    const unsigned int ranks  = Utilities::MPI::n_mpi_processes(comm);
    const double updates      = loop_seconds > 0 ? bonds_global * steps_done / loop_seconds : 0;
    const double e_ref        = std::abs(initial_energy) + std::abs(external_work);
    const bool   explicit_run = solver_type == "Verlet";

    pcout << "\nPeriDeal summary\n"
          << "  points:                 " << cloud.n_global() << "\n"
          << "  bonds:                  " << std::setprecision(12) << bonds_global << " (directed)\n"
          << "  steps:                  " << steps_done << "\n"
          << "  wall time:              " << format_seconds(setup_seconds + loop_seconds)
          << " (set-up " << format_seconds(setup_seconds) << ", " << (solver_type == "QuasiStatic" ? "load steps " : "time loop ")
          << format_seconds(loop_seconds) << ")\n";
    if (explicit_run)
      pcout << "  bond updates per second: " << sci(updates / 1e6, 4) << " M (" << sci(updates / 1e6 / ranks, 4)
            << " M per rank)\n";
    else
      pcout << "  tangent:                " << describe_tangent() << "\n";
    pcout << "  peak memory:            " << mib(peak_sum) << " over all ranks (largest rank " << mib(peak_max)
          << "); " << sci(peak_sum / std::max(1.0, bonds_global), 3) << " bytes per bond, "
          << sci(peak_sum / std::max<double>(1, cloud.n_global()), 4) << " bytes per point\n";
    pcout << "  scene memory:           " << mib(peak_sum - startup_sum)
          << " over all ranks: peak minus the start-up footprint (libraries; " << mib(startup_max)
          << " per rank); " << sci((peak_sum - startup_sum) / std::max(1.0, bonds_global), 3)
          << " bytes per bond\n";
    if (explicit_run)
      {
        pcout << "  stable time step:       " << sci(dt_stable, 6) << ", used " << sci(dt, 6);
        if (shortened_steps > 0)
          pcout << "; " << shortened_steps << " steps shortened to keep max |v| dt <= "
                << sci(max_spacing_fraction, 2) << " point spacings, the shortest " << sci(shortest_dt, 6);
        pcout << "\n";
      }
    else if (solver_type == "Newmark")
      pcout << "  time step:              " << sci(dt, 6) << " (" << sci(dt / dt_stable, 3)
            << " x the explicit stable estimate " << sci(dt_stable, 6) << ")\n";
    const bool dissipation = track_dissipation && !broken.empty();
    if (dissipation)
      pcout << "  dissipated energy:      " << sci(dissipated_energy, 6)
            << " (released by broken bonds: their strain energy where they broke)\n";
    if (e_ref > 0)
      pcout << "  energy balance error:   "
            << sci((last_kinetic_energy + last_strain_energy + dissipated_energy - initial_energy - external_work) /
                     e_ref,
                   3)
            << (dissipation ? " (kinetic + strain + dissipated - initial - external work, relative)\n" :
                              " (kinetic + strain - initial - external work, relative)\n");
    pcout << "  warnings:               " << (warnings.empty() ? std::string("none") : std::to_string(warnings.size()))
          << "\n";
    for (const auto &w : warnings)
      pcout << "Warning: " << w << "\n";
    pcout << std::flush;
    timer.print_summary();
    // Where ranks wait for each other: the spread of every section over ranks.
    if (ranks > 1)
      timer.print_wall_time_statistics(comm);
  }

  void
  Simulation::stop_if_interrupted_in_setup()
  {
    const int signal = interrupt_signal(comm);
    if (signal != 0)
      throw Interrupted(signal, "interrupted by " + signal_name(signal) +
                                  " during set-up, before the first step: nothing written");
  }

  void
  Simulation::stop_interrupted(const unsigned int step, const double time, const unsigned int n_steps,
                               const double loop_seconds)
  {
    const int signal = interrupt_signal(comm);
    // The state at the stop goes to disk as a run's last step would: what
    // the step's own output (with @p n_steps) did not write yet.
    const bool wrote       = output.is_output_step(step, n_steps);
    const bool add_globals = output.is_globals_step(step, step) && !output.is_globals_step(step, n_steps);
    const bool add_fields  = output.is_field_step(step, step) && !output.is_field_step(step, n_steps);
    if (!wrote)
      compute_forces(true); // the energies (explicit steps compute them at output steps only)
    if (add_globals || add_fields)
      write_output(step, time, add_globals, add_fields);
    else if (!wrote)
      global_quantities(step, time); // the summary's energy balance
    const std::string message = "interrupted by " + signal_name(signal) + " at step " + std::to_string(step) +
                                " (t = " + sci(time, 6) + "): " +
                                (output.is_output_step(step, step) ?
                                   "the output holds steps up to " + std::to_string(step) :
                                   std::string("nothing written (Output/Frequency = 0)"));
    // Said before the summary: mpirun, stopping the job, may drop what a
    // rank writes last.
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      std::cerr << "Error: " << message << std::endl;
    print_summary(loop_seconds, step);
    throw Interrupted(signal, message, /*reported=*/true);
  }

  // ----------------------------------------------------------------- the run

  void
  Simulation::dry_run()
  {
    dry_run_mode = true;
    setup();
    stop_if_interrupted_in_setup();
    print_setup_report();
    {
      const AvailableMemory available = available_memory(comm);
      if (std::isfinite(available.bytes_per_rank))
        pcout << "  memory available:  " << mib(available.bytes_per_rank) << " per rank (" << available.limited_by
              << ")\n";
    }
    if (solver_type != "Verlet")
      {
        setup_implicit(solver_type == "QuasiStatic");
        pcout << "  tangent:           " << describe_tangent() << "\n";
      }
    pcout << "Dry run: set-up done, no time step taken." << std::endl;
  }

  void
  Simulation::evaluate_initial_state()
  {
    update_virtual_points();
    displacement.update_ghost_values();
    compute_forces(true);
  }

  void
  Simulation::record_initial_state(const unsigned int n_steps, const double time)
  {
    const auto row = global_quantities(0, time);
    initial_energy = row[2].second + row[3].second;
    // Far from t = 0 a double cannot hold t + dt: time would stall (t + dt
    // == t) or advance in steps other than dt, silently. 1e-10 leaves each
    // step's time exact to 1e-6 of dt.
    const double latest = std::max(std::abs(time), std::abs(time + n_steps * dt));
    AssertThrow(dt > 1e-10 * latest,
                ExcMessage("Solver/Initial time: at t = " + sci(latest, 6) + " the time step " + sci(dt, 6) +
                           " is below the resolution of the time (1e-10 of t): t + dt would not be t plus the "
                           "step. Count the time from 0 (Initial time = 0, Final time = the duration)"));
    if (output.is_output_step(0, n_steps))
      write_output(0, time, output.is_globals_step(0, n_steps), output.is_field_step(0, n_steps));
  }

  double
  Simulation::point_damage(const unsigned int i) const
  {
    if (broken.empty())
      return 0.0;
    double all = 0, intact = 0;
    for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
      {
        const double V = cloud.volume[bonds.neighbor[b]] * bonds.fraction(b);
        all += V;
        intact += broken[b] ? 0 : V;
      }
    return 1 - intact / all;
  }

  double
  Simulation::point_stretch(const unsigned int i) const
  {
    double       largest = -std::numeric_limits<double>::max();
    const double *u = displacement.begin();
    for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
      {
        if (!broken.empty() && broken[b])
          continue;
        const unsigned int j  = bonds.neighbor[b];
        const auto         xi = cloud.bond_vector(i, j);
        double             r0 = 0, r = 0;
        for (unsigned int d = 0; d < dim; ++d)
          {
            const double y = xi[d] + u[dim * j + d] - u[dim * i + d];
            r0 += xi[d] * xi[d];
            r += y * y;
          }
        largest = std::max(largest, std::sqrt(r / r0) - 1);
      }
    return largest == -std::numeric_limits<double>::max() ? 0 : largest;
  }

  double
  Simulation::point_spacing() const
  {
    double h = std::numeric_limits<double>::max();
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (mass_density[i] > 0)
        h = std::min(h, std::cbrt(cloud.volume[i]));
    return Utilities::MPI::min(h, comm);
  }

  double
  Simulation::fastest_bonded_speed() const
  {
    // A point whose bonds are all broken interacts with nothing: it may fly
    // at any speed. Its family is looked at only if it is the fastest yet.
    double fastest = 0;
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      {
        const double *v = velocity.begin() + dim * i;
        const double  s = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        if (s <= fastest || mass_density[i] == 0)
          continue;
        bool bonded = broken.empty();
        for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1] && !bonded; ++b)
          bonded = !broken[b];
        if (bonded)
          fastest = s;
      }
    return std::sqrt(Utilities::MPI::max(fastest, comm));
  }

  double
  Simulation::released_energy(std::vector<std::uint8_t> &mask_before)
  {
    const auto strain_energy = [&]() {
      double e = 0;
      for (unsigned int i = 0; i < cloud.n_owned(); ++i)
        e += energy_density[i] * cloud.volume[i];
      return e;
    };
    const bool allowed = breaking_allowed;
    breaking_allowed   = false;
    broken.swap(mask_before);
    compute_forces(true);
    const double before = strain_energy();
    broken.swap(mask_before);
    compute_forces(true);
    breaking_allowed = allowed;
    return Utilities::MPI::sum(before - strain_energy(), comm);
  }

  BestPoint
  Simulation::fastest_point() const
  {
    BestPoint fastest(BestPoint::Order::largest);
    const double *v = velocity.begin();
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (!is_virtual(i)) // a virtual point follows the FE nodes, looked at below
        fastest.consider(std::hypot(v[3 * i], v[3 * i + 1], v[3 * i + 2]), cloud.gid[i], &cloud.X[3 * i]);
    if (has_continuum) // FE nodes: one velocity component per DoF
      for (const auto &node : continuum->nodes)
        fastest.consider(std::abs(continuum->V.local_element(node.local)),
                         continuum->V.get_partitioner()->local_to_global(node.local), &node.x[0],
                         BestPoint::Kind::fe_dof);
    return fastest.global(comm);
  }

  std::string
  Simulation::locate_nonfinite()
  {
    // The first point (smallest global id; then FE DoFs) with a non-finite
    // displacement, velocity or force: the same on any number of ranks.
    BestPoint     first(BestPoint::Order::smallest);
    const auto    finite = [](const VectorType &w, const unsigned int k) { return std::isfinite(w.local_element(k)); };
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      for (unsigned int d = 0; d < dim; ++d)
        if (!finite(velocity, dim * i + d) || !finite(displacement, dim * i + d) || !finite(force, dim * i + d))
          {
            first.consider(0, cloud.gid[i], &cloud.X[3 * i]);
            break;
          }
    if (has_continuum)
      for (const auto &node : continuum->nodes)
        if (!finite(continuum->U, node.local) || !finite(continuum->V, node.local) ||
            !finite(continuum->F, node.local))
          first.consider(0, continuum->U.get_partitioner()->local_to_global(node.local), &node.x[0],
                         BestPoint::Kind::fe_dof);
    const BestPoint where = first.global(comm);
    if (where.found)
      return where.describe();
    // Finite values whose kinetic energy overflows.
    const BestPoint fastest = fastest_point();
    return "the kinetic energy overflows (no value is non-finite yet): the fastest " + fastest.describe() +
           ", speed " + sci(fastest.value);
  }

  void
  Simulation::run()
  {
    setup();
    stop_if_interrupted_in_setup();
    print_setup_report();
    if (solver_type == "QuasiStatic")
      {
        run_quasistatic();
        return;
      }
    if (solver_type == "Newmark")
      {
        run_newmark();
        return;
      }

    unsigned int n_steps = requested_steps;
    if (n_steps == 0)
      {
        // Counted in double first: steps are numbered in 32 bits, and a
        // count that wrapped would silently replace dt by another step.
        const double steps = std::ceil((final_time - initial_time) / dt - 1e-9);
        AssertThrow(steps <= double(std::numeric_limits<unsigned int>::max()),
                    ExcMessage("Solver/Final time: (Final time - Initial time) / dt = (" + sci(final_time, 6) +
                               " - " + sci(initial_time, 6) + ") / " + sci(dt, 6) +
                               (fixed_dt > 0 ? std::string(" (Solver/Verlet/Fixed dt)") :
                                               " (the stable time step x Solver/Verlet/Safety factor " +
                                                 sci(safety_factor, 3) + ")") +
                               " is " + sci(steps, 4) + " steps, more than the " +
                               std::to_string(std::numeric_limits<unsigned int>::max()) +
                               " a run can number: shorten the run" +
                               (fixed_dt > 0 ? std::string(" or take a larger Fixed dt") :
                                               std::string(" or use coarser cells (a larger stable step)"))));
        n_steps = std::max(1u, static_cast<unsigned int>(steps));
        dt      = (final_time - initial_time) / n_steps;
      }
    stop_if_interrupted_in_setup();
    output.initialize(comm);

    const unsigned int n       = cloud.n_owned();
    const unsigned int entries = dim * n;
    apply_initial_conditions();
    evaluate_initial_state();
    record_initial_state(n_steps, initial_time);
    for (unsigned int k = 0; k < constraints.size(); ++k)
      constraint_force[k] = force.local_element(dim * constraints[k].point + constraints[k].component);

    // The constrained entries (the rest follow the equations of motion).
    std::vector<bool> constrained(entries, false);
    for (const auto &c : constraints)
      constrained[dim * c.point + c.component] = true;

    std::vector<double> inverse_density(n);
    for (unsigned int i = 0; i < n; ++i)
      inverse_density[i] = mass_density[i] > 0 ? 1 / mass_density[i] : 0.0; // virtual points follow the FE field
    std::vector<double> u_previous(entries), v_previous(entries);
    std::vector<std::uint8_t> broken_before; // the bonds' state before a step's breaks

    // The FE nodes of continuum blocks: the same velocity-Verlet steps with
    // the lumped mass, over the owned DoFs free of hanging-node constraints.
    const std::vector<unsigned int> no_dofs;
    const std::vector<unsigned int> &fe_free = has_continuum ? continuum->free : no_dofs;
    std::vector<double>             fe_inverse_mass(fe_free.size()), U_previous(fe_free.size()),
      V_previous(fe_free.size());
    std::vector<std::uint8_t> fe_constrained;
    std::vector<int>          constrained_free; // per node constraint: index into fe_free, -1: none
    if (has_continuum)
      {
        fe_constrained = fe_prescribed_flags();
        for (unsigned int j = 0; j < fe_free.size(); ++j)
          fe_inverse_mass[j] = fe_constrained[fe_free[j]] ? 0.0 : 1 / continuum->mass.local_element(fe_free[j]);
        for (unsigned int k = 0; k < node_constraints.size(); ++k)
          {
            const unsigned int local = continuum->nodes[node_constraints[k].node].local;
            node_constraint_force[k] = continuum->F.local_element(local);
            // Its place among the free DoFs; a hanging node follows its masters.
            const auto j = std::lower_bound(fe_free.begin(), fe_free.end(), local);
            constrained_free.push_back(j != fe_free.end() && *j == local ? j - fe_free.begin() : -1);
          }
      }
    const bool fe_hanging = has_continuum && Utilities::MPI::sum(continuum->hanging.n_constraints(), comm) > 0;
    // The loads at the start of a step (constant loads: the same as at its end).
    std::vector<double> body_previous(body_force), load_previous;
    if (has_continuum && continuum->load.size() > 0)
      for (const unsigned int k : fe_free)
        load_previous.push_back(continuum->load.local_element(k));

    pcout << "Time integration: " << n_steps << " steps of " << sci(dt, 6) << " from t = " << initial_time
          << (fixed_dt == 0 ? " (shorter while a point moves more than " + sci(max_spacing_fraction, 2) +
                                " point spacings per step)" :
                              "")
          << std::endl;
    const auto start        = std::chrono::steady_clock::now();
    auto       last_print   = start;
    double     last_percent = 0;
    unsigned int step       = 0;
    double       time       = initial_time;
    double *const u = displacement.begin();
    double *const v = velocity.begin();
    double *const f = force.begin();
    // The automatic step also keeps max |v| dt <= max_spacing_fraction h
    // (see there); a fixed one is only warned about.
    const bool   adaptive   = fixed_dt == 0;
    const double dt_elastic = dt, spacing = point_spacing();
    double       speed      = fastest_bonded_speed();
    bool         fast_warned = false;
    for (step = 1;; ++step)
      {
        if (adaptive && speed * dt_elastic > max_spacing_fraction * spacing)
          {
            dt = max_spacing_fraction * spacing / speed;
            ++shortened_steps;
            shortest_dt = std::min(shortest_dt, dt);
          }
        else
          dt = dt_elastic;
        // With Number of steps or a fixed step: n_steps steps; else up to
        // Final time, the last step shortened to land on it.
        const bool counted = requested_steps > 0 || !adaptive;
        const bool last    = counted ? step == n_steps : time + dt * (1 + 1e-9) >= final_time;
        if (last && !counted)
          dt = final_time - time;
        const double new_time = last && !counted    ? final_time :
                                shortened_steps > 0 ? time + dt :
                                                      initial_time + step * dt;
        const unsigned int steps_now = counted ? n_steps : last ? step : 0; // for the output steps
        {
          TimerOutput::Scope t(timer, "time integration");
          std::copy(u, u + entries, u_previous.begin());
          std::copy(v, v + entries, v_previous.begin());
          // Half kick and drift; the force already holds the body force.
          for (unsigned int k = 0; k < entries; ++k)
            {
              v[k] += 0.5 * dt * f[k] * inverse_density[k / dim];
              u[k] += dt * v[k];
            }
          if (has_continuum)
            {
              double *const U = continuum->U.begin(), *const V = continuum->V.begin();
              const double *const F = continuum->F.begin();
              for (unsigned int j = 0; j < fe_free.size(); ++j)
                {
                  const unsigned int k = fe_free[j];
                  U_previous[j]        = U[k];
                  V_previous[j]        = V[k];
                  V[k] += 0.5 * dt * F[k] * fe_inverse_mass[j];
                  U[k] += dt * V[k];
                }
            }
          apply_prescribed(new_time, dt);
          if (fe_hanging)
            continuum->hanging.distribute(continuum->U);
          if (loads_depend_on_time)
            {
              // The work of a load over the step is the trapezoid of its two ends.
              body_previous = body_force;
              for (unsigned int j = 0; j < load_previous.size(); ++j)
                load_previous[j] = continuum->load.local_element(fe_free[j]);
              evaluate_loads(new_time);
            }
        }
        {
          TimerOutput::Scope t(timer, "ghost exchange");
          update_virtual_points();
          displacement.update_ghost_values();
        }
        const bool output_step = output.is_output_step(step, steps_now);
        if (track_dissipation && !broken.empty())
          broken_before = broken;
        const std::size_t broken_so_far = broken_bond_count;
        compute_forces(output_step);

        double ke = 0, work = 0;
        {
          TimerOutput::Scope t(timer, "time integration");
          for (unsigned int k = 0; k < entries; ++k)
            v[k] += 0.5 * dt * f[k] * inverse_density[k / dim];
          // Prescribed velocities stay as prescribed.
          for (unsigned int c = 0; c < constraints.size(); ++c)
            {
              const Constraint &con = constraints[c];
              const unsigned int e  = dim * con.point + con.component;
              const BoundaryCondition &bc = conditions[con.condition];
              if (bc.type == BoundaryCondition::Type::prescribed_velocity)
                v[e] = bc.value->value(cloud.position(con.point), new_time, cloud.hash(con.point));
              else
                v[e] = (u[e] - u_previous[e]) / dt;
              // Work of the reaction: the change of kinetic energy of the
              // constrained entry minus the work of the internal force on it.
              const double mass = mass_density[con.point] * cloud.volume[con.point];
              work += 0.5 * mass * (v[e] * v[e] - v_previous[e] * v_previous[e]) -
                      0.5 * (constraint_force[c] + f[e]) * cloud.volume[con.point] * (u[e] - u_previous[e]);
              constraint_force[c] = f[e];
            }
          if (!body_force.empty())
            for (unsigned int k = 0; k < entries; ++k)
              if (!constrained[k])
                work += 0.5 * (body_force[k] + body_previous[k]) * cloud.volume[k / dim] * (u[k] - u_previous[k]);
          for (unsigned int i = 0; i < n; ++i)
            ke += 0.5 * mass_density[i] * cloud.volume[i] *
                  (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
          if (has_continuum)
            {
              double *const U = continuum->U.begin(), *const V = continuum->V.begin();
              const double *const F = continuum->F.begin(), *const M = continuum->mass.begin();
              for (unsigned int j = 0; j < fe_free.size(); ++j)
                {
                  const unsigned int k = fe_free[j];
                  V[k] += 0.5 * dt * F[k] * fe_inverse_mass[j];
                }
              // The same bookkeeping as for the prescribed point entries;
              // F is a nodal force, M a nodal mass.
              for (unsigned int c = 0; c < node_constraints.size(); ++c)
                {
                  const auto              &con  = node_constraints[c];
                  const auto              &node = continuum->nodes[con.node];
                  const BoundaryCondition &bc   = conditions[con.condition];
                  const unsigned int       k    = node.local;
                  if (constrained_free[c] < 0)
                    continue;
                  const unsigned int j = constrained_free[c];
                  if (bc.type == BoundaryCondition::Type::prescribed_velocity)
                    V[k] = bc.value->value(node.x, new_time, 0);
                  else
                    V[k] = (U[k] - U_previous[j]) / dt;
                  work += 0.5 * M[k] * (V[k] * V[k] - V_previous[j] * V_previous[j]) -
                          0.5 * (node_constraint_force[c] + F[k]) * (U[k] - U_previous[j]);
                  node_constraint_force[c] = F[k];
                }
              if (continuum->load.size() > 0)
                for (unsigned int j = 0; j < fe_free.size(); ++j)
                  if (!fe_constrained[fe_free[j]])
                    work += 0.5 * (continuum->load.local_element(fe_free[j]) + load_previous[j]) *
                            (U[fe_free[j]] - U_previous[j]);
              ke += continuum->local_kinetic_energy();
            }
        }
        if (loads_depend_on_time)
          for (const double b : body_force)
            if (!std::isfinite(b))
              bad_condition = conditions.size(); // reported below by a collective search
        // The last entry: ranks that have received SIGTERM or SIGINT (the step
        // is finished, written if an output step, then the run stops).
        double sums[5] = {ke, work, double(bad_condition), double(broken_bond_count - broken_so_far),
                          local_interrupt_signal() != 0 ? 1.0 : 0.0};
        {
          TimerOutput::Scope t(timer, "global sums");
          Utilities::MPI::sum(ArrayView<const double>(sums, 5), comm, ArrayView<double>(sums, 5));
        }
        ke = sums[0];
        external_work += sums[1];
        if (track_dissipation && sums[3] > 0)
          {
            // Leaves the same forces (same state and bonds) for the next kick.
            TimerOutput::Scope t(timer, "dissipation");
            dissipated_energy += released_energy(broken_before);
          }
        if (sums[2] > 0)
          {
            // Name the condition (collective), then stop.
            check_condition_values(first_nonfinite_condition(new_time), new_time);
            AssertThrow(false, ExcMessage("a boundary condition gave a non-finite value at t = " + sci(new_time, 6)));
          }

        const double reference = std::abs(initial_energy) + std::abs(external_work);
        const bool   nonfinite = !std::isfinite(ke);
        // With nothing put in yet (a load ramped from zero: its work is
        // counted one drift after the kick it causes) there is no scale;
        // a blow-up from rest still ends non-finite.
        const bool   exploding = !nonfinite && ke > 0 && reference > 0 && ke > energy_growth_limit * reference;
        if (nonfinite || exploding)
          {
            std::string where = nonfinite ? locate_nonfinite() : "";
            if (exploding)
              {
                const BestPoint fastest = fastest_point();
                where = "fastest " + fastest.describe() + ", speed " + sci(fastest.value);
              }
            const std::string cause =
              dt > dt_stable ?
                "the time step " + sci(dt) + " exceeds the stable estimate " + sci(dt_stable) +
                  ": lower Solver/Verlet/Fixed dt, or set it to 0 for the automatic step" :
                "loading or an initial state beyond what the material carries, or a time step too "
                "close to the limit (lower Solver/Verlet/Safety factor)";
            // Write the last good state, then stop.
            std::copy(u_previous.begin(), u_previous.end(), u);
            std::copy(v_previous.begin(), v_previous.end(), v);
            for (unsigned int j = 0; j < fe_free.size(); ++j)
              {
                continuum->U.local_element(fe_free[j]) = U_previous[j];
                continuum->V.local_element(fe_free[j]) = V_previous[j];
              }
            if (fe_hanging)
              continuum->hanging.distribute(continuum->U);
            update_virtual_points();
            displacement.update_ghost_values();
            if (output.frequency > 0)
              {
                compute_forces(true);
                write_output(step - 1, time);
              }
            AssertThrow(false,
                        ExcMessage(std::string(nonfinite ? "the solution became non-finite" :
                                                           "the kinetic energy grew to " + sci(ke) + ", more than " +
                                                             sci(energy_growth_limit, 3) + " times the energy put in (" +
                                                             sci(reference) + ")") +
                                   " at step " + std::to_string(step) + " (t = " + sci(new_time, 6) + "), " +
                                   where + ". Likely cause: " + cause +
                                   (output.frequency > 0 ? ". The last good state is written as step " +
                                                             std::to_string(step - 1) + "." :
                                                           "")));
          }
        time = new_time;
        if (output_step)
          write_output(step, time, output.is_globals_step(step, steps_now), output.is_field_step(step, steps_now));
        if (sums[4] > 0)
          {
            const double loop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            dt = dt_elastic; // for the summary
            stop_interrupted(step, time, steps_now, loop_seconds);
          }

        if (adaptive || !fast_warned)
          speed = fastest_bonded_speed();
        if (!adaptive && !fast_warned && speed * dt > max_spacing_fraction * spacing)
          {
            fast_warned = true;
            warnings.push_back("step " + std::to_string(step) + " (t = " + sci(time, 6) +
                               "): a point with intact bonds moves " + sci(speed * dt / spacing, 3) +
                               " point spacings per step (|v| dt / h; the automatic step keeps this below " +
                               sci(max_spacing_fraction, 2) +
                               "): it outruns its neighbours' forces and the run gains energy; lower "
                               "Solver/Verlet/Fixed dt, or set it to 0 for the automatic step");
          }

        const auto   now     = std::chrono::steady_clock::now();
        const double percent = counted ? 100.0 * step / n_steps :
                                         100.0 * (time - initial_time) / (final_time - initial_time);
        if (percent - last_percent >= 10 || std::chrono::duration<double>(now - last_print).count() > 30 || last)
          {
            const double elapsed = std::chrono::duration<double>(now - start).count();
            pcout << "  " << std::setw(5) << std::fixed << std::setprecision(1) << percent << std::defaultfloat
                  << "%  step " << step << (counted ? "/" + std::to_string(n_steps) : "")
                  << "  t = " << sci(time, 6) << "  dt = " << sci(dt, 4) << "  ETA "
                  << format_seconds(percent > 0 ? elapsed * (100 - percent) / percent : 0) << std::endl;
            last_percent = percent;
            last_print   = now;
          }
        if (last)
          break;
      }
    const double loop_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    dt = dt_elastic; // for the summary
    if (!output.is_output_step(step, step))
      {
        // The energy balance needs the final strain energy.
        compute_forces(true);
        global_quantities(step, time);
      }
    print_summary(loop_seconds, step);
  }
} // namespace perideal
