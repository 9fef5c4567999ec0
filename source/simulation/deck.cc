// The parameter file: declared from the registries, read in three passes
// (base/input.h), parsed into a Deck.

#include <perideal/base/format.h>
#include <perideal/model/force_model.h>
#include <perideal/simulation/deck.h>
#include <perideal/solver/time_integrator.h>

#include <deal.II/base/utilities.h>

#include <cctype>
#include <limits>

namespace perideal
{
  using namespace dealii;

  Deck::Deck()  = default;
  Deck::~Deck() = default;

  // ---------------------------------------------------------------- parameters

  namespace
  {
    /// A section of named models of one registry (Materials, Damage models):
    /// Names, and per name its Model key (@p declare_model_entry) and the
    /// chosen model's own keys.
    template <class Interface>
    void
    declare_model_section(ParameterHandler                         &prm,
                          const std::string                        &section,
                          const std::map<std::string, std::string> &models,
                          void (*declare_model_entry)(ParameterHandler &))
    {
      std::string noun = section;
      noun[0]          = std::tolower(noun[0]);
      prm.enter_subsection(section);
      declare_names_entry(prm, noun);
      for (const auto &[name, model] : models)
        {
          prm.enter_subsection(name);
          declare_model_entry(prm);
          if (!model.empty())
            Registry<Interface>::instance().get(model, section + "/" + name + "/Model").declare(prm);
          prm.leave_subsection();
        }
      prm.leave_subsection();
    }
  } // namespace

  namespace
  {
    /// The keys of Solver, or of a stage (Solver stages/NAME: no Initial
    /// time, its own output frequencies).
    void
    declare_solver_entries(ParameterHandler &prm, const bool stage)
    {
      {
        std::string doc = "The time integrator, one of:";
        for (const auto &[name, entry] : Registry<TimeIntegrator>::instance().all())
          doc += " " + name + ": " + entry.documentation;
        prm.declare_entry("Type", "Verlet", Registry<TimeIntegrator>::instance().selection(), doc);
      }
      if (!stage)
        prm.declare_entry("Initial time", "0", Patterns::Double(), "Start time.");
      else
        {
          prm.declare_entry("Output frequency", "-1", Patterns::Integer(-1),
                            "Output/Frequency for the steps of this solver (-1: Output/Frequency's); the "
                            "last step of each solver is written.");
          prm.declare_entry("Globals frequency", "-1", Patterns::Integer(-1),
                            "Output/Globals frequency for the steps of this solver (-1: Output's).");
          prm.declare_entry("Velocity after quasistatic", "rest", Patterns::Selection("rest|load step"),
                            "The velocity this stage starts with when the solver before it is QuasiStatic "
                            "(after any other, the velocity it ended with). rest: the points free of "
                            "Prescribed displacement conditions at rest (a quasistatic state is an equilibrium "
                            "reached without motion), the prescribed ones at their condition's rate. load step: "
                            "every point at the velocity of the last load step, (u_n - u_(n-1)) / dt, dt the "
                            "load step's length: Peridigm's hand-off from QuasiStatic to the next solver (the "
                            "converter writes it). The kinetic energy this gives is added to the energy put in "
                            "(the summary's balance). A quasistatic stage starts at rest either way.");
        }
      prm.declare_entry("Final time", "0", Patterns::Double(), "End time. The number of steps is ceil((final - initial)/dt), and dt is then shortened to land on the final time exactly (Verlet steps shortened for fast points, see Verlet/Fixed dt, add steps).");
      prm.declare_entry("Number of steps", "0", Patterns::Integer(0), "If positive: run exactly this many steps of dt and ignore Final time.");
      prm.declare_entry("Energy growth limit", "10", Patterns::Double(1),
                        "Stop when the kinetic energy exceeds this factor times (initial kinetic + "
                        "strain energy + work of external forces): the run is unstable.");
      prm.declare_entry("Track dissipated energy", "true", Patterns::Bool(),
                        "With a damage model: sum the strain energy that bond damage releases (at the state "
                        "where it happened, with the damage before minus after) into the globals column "
                        "released_energy and the closing summary's energy balance, which then checks that the "
                        "run makes no energy. PMB, LPS, Elastic plastic and Viscoelastic need one pass over the "
                        "bonds of the points whose bonds changed (doc/examples/fragmenting_cylinder_reduced, 2 "
                        "ranks: time loop 2.0 s instead of 1.8 s); the correspondence models evaluate those "
                        "points twice more (their cube: +11%). "
                        "false: the summary says that its balance includes the untracked release.");
      prm.enter_subsection("Implicit");
      ImplicitParameters::declare_parameters(prm);
      prm.leave_subsection();
      // Each integrator's own keys (Verlet: subsection Verlet).
      for (const auto &[name, entry] : Registry<TimeIntegrator>::instance().all())
        entry.declare(prm);
    }
  } // namespace

  void
  declare_parameters(ParameterHandler &prm, const DeckNames &names)
  {
    prm.enter_subsection("Discretization");
    Scene::declare_parameters(prm);
    declare_named_section(prm, "Regions", "regions (Peridigm's node sets); 'All' is always defined", names.regions,
                          [&](const std::string &) { Region::declare_parameters(prm); });
    declare_named_section(prm, "Bond filters", "bond filters: planes no bond crosses (pre-cracks, notches)",
                          names.bond_filters, [&](const std::string &) { BondFilter::declare_parameters(prm); });
    declare_named_section(prm, "Initial damage",
                          "initial damage: bonds that start broken but stay in their families (they count in "
                          "the point damage), across a rectangle or out of a region",
                          names.initial_damage, [&](const std::string &) { InitialDamage::declare_parameters(prm); });
    prm.leave_subsection();

    declare_model_section<Material>(prm, "Materials", names.materials, declare_material_model_entry);
    declare_model_section<DamageModel>(prm, "Damage models", names.damage_models, declare_damage_model_entry);
    declare_model_section<ContactModel>(prm, "Contact models", names.contact_models, declare_contact_model_entry);
    ContactParameters::declare_parameters(prm, names.contact_interactions);

    prm.enter_subsection("Blocks");
    declare_names_entry(prm, "blocks; a cell belongs to the first block that claims it");
    for (const auto &name : names.blocks)
      {
        prm.enter_subsection(name);
        prm.declare_entry("Material", "", Patterns::Anything(), "Name of a material of Materials/Names.");
        prm.declare_entry("Damage model", "", Patterns::Anything(), "Name of a damage model of Damage models/Names; empty: no damage. A bond "
                          "between two blocks breaks at the smaller critical stretch of the two (a block "
                          "without one does not protect its bonds to a block with one). A block with a "
                          "continuous damage model (Linear softening) bonds only to blocks with the same one.");
        prm.declare_entry("Material ids", "0", Patterns::List(Patterns::Integer(0)), "The cells of the mesh with these material ids (Gmsh volume physical groups) form the block.");
        prm.declare_entry("Region", "", Patterns::Anything(), "If set, the cells whose centroid lies in this region form the block instead.");
        prm.declare_entry("Horizon", "0", Patterns::Double(0), "The block's horizon; 0: Discretization/Horizon.");
        prm.declare_entry("Type", "Peridynamic", Patterns::Selection("Peridynamic|Continuum|Rigid"),
                          "Peridynamic: one PD point per cell. Continuum: FE_Q(FE degree) linear elasticity "
                          "with the material's bulk modulus, shear modulus and density; peridynamic families "
                          "reach into its cells through virtual points (doc/coupling.md). Continuum blocks "
                          "take no damage model. Rigid: one point per cell, no bonds; the points move as one "
                          "rigid body (translation and rotation) under the force and torque of their forces "
                          "(contact, loads), with the mass and inertia of the material's density; an impactor "
                          "or indenter (doc/contact.md). Its motion may be prescribed by a condition on all its "
                          "points (it then translates only). Explicit runs only; no damage model.");
        prm.declare_entry("FE degree", "1", Patterns::Integer(1, 2), "Polynomial degree of a continuum block's FE_Q elements.");
        prm.leave_subsection();
      }
    prm.leave_subsection();

    prm.enter_subsection("Temperature");
    prm.declare_entry("Function", "", Patterns::Anything(),
                      "Temperature T as a muparser expression in x, y, z (the reference position) and t, "
                      "e.g. '20 + 100*x' or '20 + 10*t'; empty: no temperature field. Every material "
                      "strains its bonds by its Thermal expansion coefficient times T - T_ref "
                      "(doc/thermal.md). Evaluated at every point once, or at every step if it reads t.");
    prm.declare_entry("Reference temperature", "0", Patterns::Double(),
                      "T_ref: the temperature at which the body is free of thermal strain.");
    prm.leave_subsection();

    prm.enter_subsection("Coupling");
    prm.declare_entry("Scheme", "energy blending", Patterns::Selection("energy blending|force blending"),
                      "energy blending: one energy, the PD energy weighted by alpha and the FE energy by "
                      "1 - alpha across the band: symmetric tangent, internal forces that sum to zero, "
                      "energy conserved, but ghost forces at the interface under a homogeneous strain. "
                      "force blending: each FE node's acceleration is alpha times the PD one at the node "
                      "plus 1 - alpha times the FE one, each PD point's is the PD one: no ghost force "
                      "under any affine field, but neither exact global balance nor energy conservation "
                      "(measured in doc/coupling.md). Implicit runs solve its nonsymmetric tangent with "
                      "GMRES (whatever Solver/Implicit/Linear solver says).");
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

    AdaptivityParameters::declare_parameters(prm);

    declare_named_section(prm, "Boundary conditions", "initial and boundary conditions", names.conditions,
                          [&](const std::string &) { BoundaryCondition::declare_parameters(prm); });
    declare_named_section(prm, "Computes",
                          "computes: global quantities over regions, extra columns of the globals CSV",
                          names.computes, [&](const std::string &) { RegionCompute::declare_parameters(prm); });

    prm.enter_subsection("Solver");
    declare_solver_entries(prm, false);
    prm.leave_subsection();
    declare_named_section(prm, "Solver stages",
                          "solvers that run after the one of Solver, in this order (Peridigm's Solver2, "
                          "Solver3, ...): each starts from the state, time and step where the one before ended, "
                          "and continues the globals CSV and the .pvd series",
                          names.solver_stages, [&](const std::string &) { declare_solver_entries(prm, true); });

    prm.enter_subsection("Output");
    OutputWriter::declare_parameters(prm, model_output_fields());
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
    names.solver_stages = {"My stage"};
    names.bond_filters  = {"My filter"};
    names.initial_damage = {"My initial damage"};
    for (const auto &m : Registry<Material>::instance().all())
      names.materials["My " + m.first + " material"] = m.first;
    for (const auto &m : Registry<DamageModel>::instance().all())
      names.damage_models["My " + m.first + " model"] = m.first;
    for (const auto &m : Registry<ContactModel>::instance().all())
      names.contact_models["My " + m.first + " model"] = m.first;
    names.contact_interactions = {"My interaction"};
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
    set_names({"Discretization", "Initial damage"}, "My initial damage");
    set_names({"Materials"}, join(names.materials));
    set_names({"Damage models"}, join(names.damage_models));
    set_names({"Contact models"}, join(names.contact_models));
    set_names({"Contact", "Interactions"}, "My interaction");
    set_names({"Blocks"}, "My block");
    set_names({"Boundary conditions"}, "My condition");
    for (const auto &[section, models] : {std::make_pair("Materials", &names.materials),
                                           std::make_pair("Damage models", &names.damage_models),
                                           std::make_pair("Contact models", &names.contact_models)})
      for (const auto &[name, model] : *models)
        {
          prm.enter_subsection(section);
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
            << "; damage models " << Registry<DamageModel>::instance().names(", ")
            << "; contact models " << Registry<ContactModel>::instance().names(", ")
            << "; time integrators (Solver/Type) " << Registry<TimeIntegrator>::instance().names(", ")
            << "; continuum models (of every block of Type Continuum; no key chooses one yet) "
            << Registry<ContinuumModel>::instance().names(", ") << ".\n\n";
        for (const auto &m : Registry<Material>::instance().all())
          out << "- material `" << m.first << "`: " << m.second.documentation << "\n";
        for (const auto &m : Registry<DamageModel>::instance().all())
          out << "- damage model `" << m.first << "`: " << m.second.documentation << "\n";
        for (const auto &m : Registry<ContactModel>::instance().all())
          out << "- contact model `" << m.first << "`: " << m.second.documentation << "\n";
        for (const auto &m : Registry<ContinuumModel>::instance().all())
          out << "- continuum model `" << m.first << "`: " << m.second.documentation << "\n";
        out << "\n```\n";
      }
    prm.print_parameters(out, ParameterHandler::PRM);
    if (markdown)
      out << "```\n";
  }

  SolverStage::SolverStage()                   = default;
  SolverStage::SolverStage(SolverStage &&) noexcept = default;
  SolverStage::~SolverStage()                  = default;

  void
  read_deck(const std::string &file, Deck &deck)
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
      names.initial_damage = read_list(prm, {"Discretization", "Initial damage"});
      names.blocks     = read_list(prm, {"Blocks"});
      names.conditions = read_list(prm, {"Boundary conditions"});
      names.computes   = read_list(prm, {"Computes"});
      names.solver_stages = read_list(prm, {"Solver stages"});
      for (const auto &n : read_list(prm, {"Materials"}))
        names.materials[n] = "";
      for (const auto &n : read_list(prm, {"Damage models"}))
        names.damage_models[n] = "";
      for (const auto &n : read_list(prm, {"Contact models"}))
        names.contact_models[n] = "";
      names.contact_interactions = read_list(prm, {"Contact", "Interactions"});
      for (const auto &r : names.regions)
        AssertThrow(r != "All", ExcMessage("Discretization/Regions/Names: 'All' is predefined; choose another name"));
    }
    // Pass 2: the model of each material and damage model.
    {
      ParameterHandler prm;
      declare_parameters(prm, names);
      parse_input_file(prm, file, false);
      for (auto &[section, map] : std::vector<std::pair<std::string, std::map<std::string, std::string> *>>{
             {"Materials", &names.materials}, {"Damage models", &names.damage_models},
             {"Contact models", &names.contact_models}})
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
      for (const auto &[name, model] : names.contact_models)
        Registry<ContactModel>::instance().get(model, "Contact models/" + name + "/Model");
    }
    // Pass 3: everything, strictly.
    ParameterHandler prm;
    declare_parameters(prm, names);
    parse_input_file(prm, file, true);
    deck.output.keep_parameters(prm, file); // written with the output (not on --dry-run)

    prm.enter_subsection("Discretization");
    deck.scene.parse_parameters(prm);
    prm.enter_subsection("Regions");
    for (const auto &name : names.regions)
      {
        prm.enter_subsection(name);
        auto region  = std::make_unique<Region>();
        region->name = name;
        region->parse_parameters(prm, "Discretization/Regions/" + name, *deck.scene.geometry);
        deck.regions[name] = std::move(region);
        prm.leave_subsection();
      }
    prm.leave_subsection();
    prm.enter_subsection("Bond filters");
    for (const auto &name : names.bond_filters)
      {
        prm.enter_subsection(name);
        deck.bond_filters.emplace_back();
        deck.bond_filters.back().name = name;
        deck.bond_filters.back().parse_parameters(prm, "Discretization/Bond filters/" + name);
        prm.leave_subsection();
      }
    prm.leave_subsection();
    prm.enter_subsection("Initial damage");
    for (const auto &name : names.initial_damage)
      {
        const std::string path = "Discretization/Initial damage/" + name;
        prm.enter_subsection(name);
        deck.initial_damage.emplace_back();
        deck.initial_damage.back().name = name;
        deck.initial_damage.back().parse_parameters(prm, path);
        const std::string &region = deck.initial_damage.back().region;
        AssertThrow(deck.initial_damage.back().type != InitialDamage::Type::region || deck.regions.count(region),
                    ExcMessage(path + "/Region: '" + region + "' is not defined in Discretization/Regions/Names"));
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
        block.rigid         = prm.get("Type") == "Rigid";
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
        AssertThrow(!block.rigid || block.damage_name.empty(),
                    ExcMessage(path + "/Damage model: a rigid block has no bonds to break; remove the damage "
                                      "model or make the block Peridynamic"));
        AssertThrow(block.region.empty() || block.region == "All" || deck.regions.count(block.region),
                    ExcMessage(path + "/Region: '" + block.region +
                               "' is not defined in Discretization/Regions/Names"));
        if (block.horizon == 0)
          block.horizon = deck.scene.horizon;
        AssertThrow(block.horizon > 0,
                    ExcMessage(path + "/Horizon and Discretization/Horizon are both 0: "
                                      "set a positive horizon"));
        deck.blocks.push_back(std::move(block));
      }
    prm.leave_subsection();

    // One material (and damage model) instance per block: the horizon differs.
    for (auto &block : deck.blocks)
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
            block.neglect_damage = prm.get_double("Critical damage to neglect material point");
            AssertThrow(block.neglect_damage > 0 && block.neglect_damage <= 1,
                        ExcMessage("Damage models/" + block.damage_name +
                                   "/Critical damage to neglect material point must be in (0, 1] (1: never), got " +
                                   prm.get("Critical damage to neglect material point")));
            prm.leave_subsection();
            prm.leave_subsection();
          }
      }
    for (auto &block : deck.blocks)
      if (block.continuum)
        {
          deck.has_continuum = true;
          // The only continuum model so far; a key would choose it by name here.
          block.continuum_model = Registry<ContinuumModel>::instance().create("Linear elasticity", "Blocks/" + block.name + "/Type");
          block.continuum_model->initialize(*block.material);
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
      AssertThrow(region == "All" || deck.regions.count(region),
                  ExcMessage(path + "/Region: '" + region + "' is not defined in Discretization/Regions/Names"));
    };
    prm.enter_subsection("Temperature");
    deck.temperature.function  = prm.get("Function");
    deck.temperature.reference = prm.get_double("Reference temperature");
    if (deck.temperature.function.find_first_not_of(" \t") == std::string::npos)
      deck.temperature.function.clear();
    else
      {
        // A parse error now, naming the key.
        const Expression check(deck.temperature.function, "Temperature/Function");
      }
    prm.leave_subsection();

    prm.enter_subsection("Coupling");
    deck.coupling.scheme = prm.get("Scheme") == "force blending" ? CouplingParameters::Scheme::force :
                                                                   CouplingParameters::Scheme::energy;
    deck.coupling.blending_width       = prm.get_double("Blending width");
    const std::string levels           = prm.get("Virtual point levels");
    deck.coupling.virtual_point_levels = levels == "auto" ? -1 : std::stoi(levels);
    prm.leave_subsection();

    deck.adaptivity.parse_parameters(prm);

    prm.enter_subsection("Contact models");
    for (const auto &[name, model] : names.contact_models)
      {
        prm.enter_subsection(name);
        auto instance = Registry<ContactModel>::instance().get(model, "").create();
        instance->parse_parameters(prm, "Contact models/" + name);
        deck.contact.models[name] = std::move(instance);
        prm.leave_subsection();
      }
    prm.leave_subsection();
    deck.contact.parse_parameters(prm, names.contact_interactions, names.blocks);

    prm.enter_subsection("Boundary conditions");
    for (const auto &name : names.conditions)
      {
        const std::string path = "Boundary conditions/" + name;
        prm.enter_subsection(name);
        BoundaryCondition bc;
        bc.name = name;
        bc.parse_parameters(prm, path);
        require_region(path, bc.region);
        deck.conditions.push_back(std::move(bc));
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
        deck.computes.push_back(std::move(compute));
        prm.leave_subsection();
      }
    prm.leave_subsection();

    // Solver, then each stage: the same keys (a stage has no Initial time:
    // it starts where the one before ends).
    const auto parse_solver = [&](SolverParameters &solver, std::unique_ptr<TimeIntegrator> &chosen,
                                  const std::string &path, const bool stage) {
      solver.type = prm.get("Type");
      prm.enter_subsection("Implicit");
      solver.implicit.parse_parameters(prm);
      prm.leave_subsection();
      if (!stage)
        solver.initial_time = prm.get_double("Initial time");
      solver.final_time          = prm.get_double("Final time");
      solver.requested_steps     = prm.get_integer("Number of steps");
      solver.energy_growth_limit = prm.get_double("Energy growth limit");
      solver.track_dissipation   = prm.get_bool("Track dissipated energy");
      // Every registered integrator parses its own keys, so that their errors
      // show whichever runs; the chosen one checks them against the rest.
      for (const auto &[name, entry] : Registry<TimeIntegrator>::instance().all())
        {
          auto integrator = entry.create();
          integrator->parse_parameters(prm);
          if (name == solver.type)
            chosen = std::move(integrator);
        }
      for (const auto &block : deck.blocks)
        AssertThrow(!block.rigid || solver.type == "Verlet",
                    ExcMessage("Blocks/" + block.name + "/Type: " + path + "/Type is " + solver.type +
                               ", but a rigid block moves in explicit runs only (Type = Verlet): Newton's "
                               "matrix has no rows for a rigid body yet"));
      AssertThrow(!deck.contact.active() || solver.type == "Verlet",
                  ExcMessage("Contact: " + path + "/Type is " + solver.type +
                             ", but contact acts in explicit runs only (Type = Verlet): the contact force has "
                             "no tangent for Newton's method yet"));
      chosen->check_parameters(solver, deck.has_continuum);
      AssertThrow(stage || solver.requested_steps > 0 || solver.final_time > solver.initial_time,
                  ExcMessage("Solver/Final time must be after Solver/Initial time (or set "
                             "Solver/Number of steps)"));
    };
    prm.enter_subsection("Solver");
    parse_solver(deck.solver, deck.integrator, "Solver", false);
    prm.leave_subsection();
    prm.enter_subsection("Solver stages");
    double previous_end = deck.solver.requested_steps > 0 ? -std::numeric_limits<double>::max() : deck.solver.final_time;
    for (const auto &name : names.solver_stages)
      {
        prm.enter_subsection(name);
        SolverStage stage;
        stage.name = name;
        parse_solver(stage.solver, stage.integrator, "Solver stages/" + name, true);
        stage.output_frequency  = prm.get_integer("Output frequency");
        stage.globals_frequency = prm.get_integer("Globals frequency");
        stage.velocity_of_load_step = prm.get("Velocity after quasistatic") == "load step";
        {
          const std::string &before = deck.stages.empty() ? deck.solver.type : deck.stages.back().solver.type;
          AssertThrow(!stage.velocity_of_load_step || (before == "QuasiStatic" && stage.solver.type != "QuasiStatic"),
                      ExcMessage("Solver stages/" + name + "/Velocity after quasistatic = load step: " +
                                 (before != "QuasiStatic" ?
                                    "the solver before this stage is " + before +
                                      ", not QuasiStatic: its velocity is handed over as it is (use rest)" :
                                    std::string("this stage is QuasiStatic, which starts at rest (use rest)"))));
        }
        // Known now only where both ends are given; else checked when the stage starts.
        AssertThrow(stage.solver.requested_steps > 0 || stage.solver.final_time > previous_end,
                    ExcMessage("Solver stages/" + name + "/Final time (" + sci(stage.solver.final_time, 6) +
                               ") must be after the end of the solver before it (t = " + sci(previous_end, 6) +
                               "), or set Number of steps"));
        previous_end = stage.solver.requested_steps > 0 ? -std::numeric_limits<double>::max() : stage.solver.final_time;
        deck.stages.push_back(std::move(stage));
        prm.leave_subsection();
      }
    prm.leave_subsection();

    prm.enter_subsection("Output");
    deck.output.parse_parameters(prm);
    prm.leave_subsection();
    deck.adaptivity.resolve(deck.blocks);
    AssertThrow(!deck.output.wants("Temperature") || !deck.temperature.function.empty(),
                ExcMessage("Output/Variables: Temperature needs a temperature field: set Temperature/Function"));
  }
} // namespace perideal
