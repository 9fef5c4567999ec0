// The force model (force_model.h): materials and damage models per block.

#include <perideal/base/format.h>
#include <perideal/continuum/coupling.h>
#include <perideal/contact/contact.h>
#include <perideal/model/force_model.h>
#include <perideal/output/checkpoint.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/mpi.templates.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <typeinfo>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    /// Calls @p f(name, point_fields()) for every registered material and damage model.
    template <typename Function>
    void
    for_each_model(const Function &f)
    {
      for (const auto &[name, entry] : Registry<Material>::instance().all())
        f(name, entry.create()->point_fields());
      for (const auto &[name, entry] : Registry<DamageModel>::instance().all())
        f(name, entry.create()->point_fields());
    }

    /// A temperature field that strains nothing, or an expansion coefficient
    /// that nothing heats: legal (the one may be for output, the other for
    /// a later stage), but rarely meant. Deformable blocks only: continuum
    /// and rigid blocks take no thermal strain.
    void
    warn_thermal(const std::vector<Block> &blocks, const bool has_temperature, std::vector<std::string> &warnings)
    {
      std::vector<std::string> expanding; // materials with alpha != 0
      bool                     deformable = false;
      for (const auto &block : blocks)
        if (block.material && !block.continuum && !block.rigid)
          {
            deformable = true;
            if (block.material->thermal_expansion_coefficient() != 0 &&
                std::find(expanding.begin(), expanding.end(), block.material_name) == expanding.end())
              expanding.push_back(block.material_name);
          }
      if (has_temperature && deformable && expanding.empty())
        warnings.push_back("Temperature/Function is set, but the Thermal expansion coefficient of every material "
                           "of a deformable block is 0: the temperature strains nothing");
      if (!has_temperature)
        for (const auto &name : expanding)
          warnings.push_back("Materials/" + name + "/Thermal expansion coefficient is not 0, but Temperature/"
                             "Function is empty: no thermal strain acts (the body stays at the reference "
                             "temperature)");
    }

    /// Cells (or points of a Text file cloud) that no block claims are left out
    /// of the body: legal (a mesh may hold parts not simulated), but said,
    /// with their material ids and counts, lest half a cloud vanish unnoticed.
    void
    warn_unclaimed_cells(const Discretization &discretization, const MPI_Comm comm, std::vector<std::string> &warnings)
    {
      std::map<unsigned int, double> unclaimed; // material id: cells
      double                         all = 0;
      for (const auto &cell : discretization.dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            ++all;
            if (discretization.block_of_cell(cell) < 0)
              ++unclaimed[cell->material_id()];
          }
      // Every rank the same ids: the union, then the sums.
      std::set<unsigned int> ids;
      for (const auto &[id, count] : unclaimed)
        ids.insert(id);
      ids = Utilities::MPI::compute_set_union(ids, comm);
      if (ids.empty())
        return;
      std::vector<double> counts;
      for (const auto id : ids)
        counts.push_back(unclaimed.count(id) ? unclaimed[id] : 0.0);
      Utilities::MPI::sum(counts, comm, counts);
      all = Utilities::MPI::sum(all, comm);
      std::ostringstream text;
      double             total = 0;
      unsigned int       k     = 0;
      for (const auto id : ids)
        {
          text << (k > 0 ? ", " : "") << "material id " << id << ": " << counts[k];
          total += counts[k++];
        }
      std::ostringstream message;
      message << total << " of " << all << " cells (or points of a Text file cloud) belong to no block and are left "
              << "out of the body (" << text.str() << "): no Blocks/*/Material ids or Region holds them";
      warnings.push_back(message.str());
    }

    /// Blocks @p a and @p c share a damage law that depends on the horizon
    /// but have different horizons.
    void
    report_uneven_horizons(const Block &a, const Block &c)
    {
      const auto number = [](const double x) {
        std::ostringstream out;
        out << x;
        return out.str();
      };
      AssertThrow(false,
                  ExcMessage("blocks '" + a.name + "' and '" + c.name + "' share damage model '" + a.damage_name +
                             "', whose law depends on the horizon, but have different horizons (" +
                             number(a.horizon) + ", " + number(c.horizon) +
                             "): the two halves of a bond between them would break at different "
                             "energies. Give them one horizon, or separate them by more than a horizon"));
    }

    /// Blocks @p a and @p c are bonded and apply different damage laws,
    /// one of them a law of its own.
    void
    report_mixed_damage_laws(const Block &a, const Block &c)
    {
      const auto model = [](const Block &x) {
        return x.damage_name.empty() ? std::string("no damage model") : "damage model '" + x.damage_name + "'";
      };
      const bool cont = (a.damage && a.damage->continuous()) || (c.damage && c.damage->continuous());
      AssertThrow(false,
                  ExcMessage("blocks '" + a.name + "' (" + model(a) + ") and '" + c.name + "' (" + model(c) +
                             ") are within a horizon of each other, and one of them has a " +
                             (cont ? "continuous damage model" :
                                     "damage model with a law of its own (not a critical stretch)") +
                             ": the two halves of a bond between them would follow "
                             "different laws. Give both blocks the same damage model, or separate "
                             "them by more than a horizon"));
    }
  } // namespace

  std::vector<PointField>
  model_output_fields()
  {
    std::vector<PointField> out;
    for_each_model([&](const std::string &, const std::vector<PointField> &fields) {
      for (const auto &f : fields)
        if (!f.output_name.empty() &&
            std::none_of(out.begin(), out.end(), [&](const auto &o) { return o.output_name == f.output_name; }))
          out.push_back(f);
    });
    return out;
  }

  std::string
  models_with_output(const std::string &output_name)
  {
    std::string models;
    for_each_model([&](const std::string &name, const std::vector<PointField> &fields) {
      if (std::any_of(fields.begin(), fields.end(), [&](const auto &f) { return f.output_name == output_name; }))
        models += (models.empty() ? "" : " or ") + name;
    });
    return models;
  }

  ForceModel::ForceModel(Discretization &discretization, MechanicalState &mechanical, RunRecord &record,
                         const MPI_Comm comm, TimerOutput &timer)
    : blocks(discretization.blocks)
    , discretization(discretization)
    , cloud(discretization.cloud)
    , bonds(discretization.bonds)
    , mechanical(mechanical)
    , record(record)
    , comm(comm)
    , timer(timer)
  {}

  void
  ForceModel::attach(const std::vector<double> &body_force_, Coupling *coupling_)
  {
    body_force = &body_force_;
    coupling   = coupling_;
  }

  void
  ForceModel::setup()
  {
    collect_block_points();
    check_models_across_blocks();
    setup_bond_damage();
    check_damage_laws_across_blocks();
    setup_mechanical_state();
    declare_model_fields();
    initialize_models();
    setup_damage_options();
    warn_thermal(blocks, temperature_function != nullptr, record.warnings);
    if (!unclaimed_reported) // once: an adaptive rebuild's refinement changes the counts, not the fact
      warn_unclaimed_cells(discretization, comm, record.warnings);
    unclaimed_reported = true;
    if (temperature_function)
      {
        temperature_change.reinit(cloud.scalar_partitioner);
        thermal_strain.reinit(cloud.scalar_partitioner);
        update_temperature();
      }
    rigid.setup(blocks, cloud, mechanical.mass_density, comm);
    fields->update_ghost_values(FieldUse::constant);
    // The history starts from the initial state.
    fields->commit();
  }

  void
  ForceModel::collect_block_points()
  {
    for (auto &block : blocks)
      block.points.clear();
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      blocks[cloud.block[i]].points.push_back(i);
  }

  void
  ForceModel::check_models_across_blocks() const
  {
    // Bonds between blocks of different models cannot be evaluated by either.
    std::vector<std::string> model(blocks.size());
    for (unsigned int b = 0; b < blocks.size(); ++b)
      model[b] = typeid(*blocks[b].material).name();
    bool                                  mixed = false;
    std::pair<unsigned int, unsigned int> pair{0, 0};
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
        {
          const unsigned int bi = cloud.block[i], bj = cloud.block[bonds.neighbor[b]];
          if (bi != bj && model[bi] != model[bj])
            mixed = true, pair = {bi, bj};
        }
    const unsigned int any = Utilities::MPI::max(mixed ? 1u : 0u, comm);
    AssertThrow(any == 0,
                ExcMessage("blocks '" + blocks[pair.first].name + "' and '" + blocks[pair.second].name +
                           "' (or others) are within a horizon of each other but use different "
                           "material models; bonds between models are not defined: use the same "
                           "model with different parameters, or separate the blocks by more than "
                           "a horizon"));
  }

  void
  ForceModel::setup_bond_damage()
  {
    bool any_damage = false;
    continuous.assign(blocks.size(), false);
    for (unsigned int k = 0; k < blocks.size(); ++k)
      if (blocks[k].damage)
        {
          any_damage    = true;
          continuous[k] = blocks[k].damage->continuous();
          AssertThrow(!continuous[k] || blocks[k].material->supports_continuous_damage(),
                      ExcMessage("Blocks/" + blocks[k].name + ": damage model '" + blocks[k].damage_name +
                                 "' sets a continuous bond damage, which material '" + blocks[k].material_name +
                                 "' does not read (it supports binary damage only, e.g. Critical stretch)"));
        }
    // Initially broken bonds need the damage arrays even without a model.
    if (!discretization.initially_broken.empty())
      broken = discretization.initially_broken;
    else if (any_damage)
      broken.assign(bonds.n_bonds(), 0);
    for (unsigned int d = 0; d < discretization.initial_damage.size(); ++d)
      if (discretization.initially_broken_bonds[d] == 0)
        {
          const InitialDamage &entry = discretization.initial_damage[d];
          record.warnings.push_back(
            "Discretization/Initial damage/" + entry.name + " breaks no bond" +
            (entry.type == InitialDamage::Type::plane ?
               " (check its corner, vectors and lengths; the side runs along Bottom unit vector x Normal)" :
               " (its region '" + entry.region + "' holds no point)"));
        }
    if (std::find(continuous.begin(), continuous.end(), true) != continuous.end())
      damage.assign(broken.begin(), broken.end()); // d = 1 where initially broken
  }

  void
  ForceModel::check_damage_laws_across_blocks() const
  {
    // Both halves of a bond take the same d only if both owners apply the
    // same law: a bond from a block whose model decides by a law of its own
    // (not a critical stretch, which BondStretchLimits applies across blocks)
    // must end in a block with the same model, and one of the same horizon
    // if the law depends on it.
    std::vector<bool> own_law(blocks.size(), false);
    for (unsigned int k = 0; k < blocks.size(); ++k)
      own_law[k] = blocks[k].damage && !blocks[k].damage->stretch_criterion();
    if (std::find(own_law.begin(), own_law.end(), true) == own_law.end())
      return;
    // A pair of blocks as one number, the same on every rank that names
    // one: the smallest; none: the largest unsigned int.
    const unsigned int none = std::numeric_limits<unsigned int>::max();
    unsigned int       mixed = none, uneven = none;
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
        {
          const unsigned int bi = cloud.block[i], bj = cloud.block[bonds.neighbor[b]];
          const unsigned int code = std::min(bi, bj) * blocks.size() + std::max(bi, bj);
          if ((own_law[bi] || own_law[bj]) && blocks[bi].damage_name != blocks[bj].damage_name)
            mixed = code;
          else if (own_law[bi] && blocks[bi].damage->horizon_dependent() && blocks[bi].horizon != blocks[bj].horizon)
            uneven = code;
        }
    uneven = Utilities::MPI::min(uneven, comm);
    if (uneven != none)
      report_uneven_horizons(blocks[uneven / blocks.size()], blocks[uneven % blocks.size()]);
    mixed = Utilities::MPI::min(mixed, comm);
    if (mixed != none)
      report_mixed_damage_laws(blocks[mixed / blocks.size()], blocks[mixed % blocks.size()]);
  }

  void
  ForceModel::setup_mechanical_state()
  {
    mechanical.displacement.reinit(cloud.vector_partitioner);
    mechanical.velocity.reinit(cloud.vector_partitioner);
    mechanical.force.reinit(cloud.vector_partitioner);
    mechanical.mass_density.resize(cloud.n_owned());
    for (unsigned int i = 0; i < cloud.n_owned(); ++i) // virtual points: no mass of their own
      mechanical.mass_density[i] = discretization.is_virtual(i) ? 0.0 : blocks[cloud.block[i]].material->density();
  }

  void
  ForceModel::declare_model_fields()
  {
    fields           = std::make_unique<FieldStore>(cloud);
    has_stage_fields = false;
    for (const auto &block : blocks)
      if (block.damage && block.damage->uses_bond_energy())
        block.material->request_bond_energy();
    for (const auto &block : blocks)
      {
        std::vector<PointField> point = block.material->point_fields();
        std::vector<BondField>  bond  = block.material->bond_fields();
        if (block.damage)
          {
            const auto damage_point = block.damage->point_fields();
            const auto damage_bond  = block.damage->bond_fields();
            point.insert(point.end(), damage_point.begin(), damage_point.end());
            bond.insert(bond.end(), damage_bond.begin(), damage_bond.end());
          }
        for (const auto &f : point)
          {
            fields->declare(f);
            has_stage_fields |= f.use == FieldUse::stage;
          }
        for (const auto &f : bond)
          fields->declare(f, bonds.n_bonds());
      }
  }

  void
  ForceModel::initialize_models()
  {
    const ModelState state{cloud,   bonds,   nullptr, mechanical.displacement.begin(), mechanical.force.begin(),
                           nullptr, *fields};
    fused_breaking.clear();
    read_points.assign(blocks.size(), {});
    if (discretization.force_blending)
      for (const unsigned int i : discretization.node_points)
        read_points[cloud.block[i]].push_back(i);
    for (unsigned int b = 0; b < blocks.size(); ++b)
      {
        blocks[b].material->set_block(b, blocks[b].horizon);
        if (!blocks[b].rigid) // a rigid block's material gives only its density
          blocks[b].material->initialize(state, blocks[b].points);
        if (blocks[b].continuum && !discretization.force_blending) // force blending: unweighted
          AssertThrow(blocks[b].material->weight_energy(state, blocks[b].points, discretization.point_alpha.data()),
                      ExcMessage("Blocks/" + blocks[b].name + "/Type: material '" + blocks[b].material_name +
                                 "' cannot weight its energy, so it cannot be coupled to a continuum block"));
        if (blocks[b].damage)
          blocks[b].damage->initialize(*blocks[b].material, blocks[b].horizon);
        fused_breaking.emplace_back();
      }
  }

  void
  ForceModel::setup_damage_options()
  {
    neglecting = false;
    for (const auto &block : blocks)
      neglecting |= block.damage && block.neglect_damage < 1;
    n_neglected     = 0;
    neglect_checked = std::numeric_limits<std::size_t>::max(); // check at the first evaluation
    if (neglecting)
      neglected.reinit(cloud.scalar_partitioner);
    time_dependent_limits = false;
    for (const auto &block : blocks)
      time_dependent_limits |= block.damage && block.damage->stretch_criterion() && block.damage->time_dependent();
    stretch_limits = BondStretchLimits(blocks.size(), cloud, bonds, comm);
    set_stretch_limits();
  }

  void
  ForceModel::set_stretch_limits()
  {
    std::vector<double> within(blocks.size(), 0.0), across(blocks.size(), 0.0);
    for (unsigned int b = 0; b < blocks.size(); ++b)
      if (blocks[b].damage && blocks[b].damage->stretch_criterion())
        {
          within[b] = blocks[b].damage->critical_stretch(time);
          across[b] = blocks[b].damage->interface_critical_stretch(time);
        }
    stretch_limits.set(within, across);
    fused.assign(blocks.size(), false);
    limit_at.resize(blocks.size());
    for (unsigned int b = 0; b < blocks.size(); ++b)
      {
        StretchBreaking &fuse    = fused_breaking[b];
        const Material  &material = *blocks[b].material;
        fuse.squared_limit       = stretch_limits.common_limit(b);
        fuse.broken              = broken.data();
        // A damage model of another kind runs its own pass (damage_pass()).
        const bool by_stretch = !blocks[b].damage || blocks[b].damage->stretch_criterion();
        const bool by_far_end = fuse.squared_limit == 0 && by_stretch && stretch_limits.may_break(b) &&
                                material.fuses_limits_by_block();
        limit_at[b].clear();
        if (by_far_end)
          {
            const double *row = stretch_limits.limits_of(b);
            for (const unsigned short block : cloud.block)
              limit_at[b].push_back(row[block]);
          }
        fuse.limit_at = limit_at[b].data();
        fused[b]      = material.fuses_stretch_criterion() && (fuse.squared_limit > 0 || by_far_end);
      }
  }

  bool
  ForceModel::add_tangent(TangentRows &rows) const
  {
    const ModelState state{cloud,
                           bonds,
                           broken.empty() ? nullptr : broken.data(),
                           mechanical.displacement.begin(),
                           mechanical.force.begin(),
                           nullptr,
                           *fields};
    for (unsigned int k = 0; k < blocks.size(); ++k)
      if (!blocks[k].points.empty() && !blocks[k].rigid &&
          !blocks[k].material->add_tangent(block_state(state, k), blocks[k].points, rows))
        return false;
    return true;
  }

  void
  ForceModel::compute_forces(const bool with_energy)
  {
    const unsigned int n = cloud.n_owned();
    std::fill(mechanical.force.begin(), mechanical.force.begin() + dim * n, 0.0);
    if (with_energy)
      mechanical.energy_density.assign(n, 0.0);
    ModelState state{cloud,
                     bonds,
                     broken.empty() ? nullptr : broken.data(),
                     mechanical.displacement.begin(),
                     mechanical.force.begin(),
                     with_energy ? mechanical.energy_density.data() : nullptr,
                     *fields};
    state.time = time;
    state.dt   = dt;
    // A block whose material applies its critical stretch in its own first
    // bond pass (fused_breaking) gets it there; other damage models run their
    // own pass first.
    const auto fused_state = [&](const unsigned int k) {
      ModelState s = block_state(state, k);
      s.breaking   = breaking_allowed && fused[k] ? &fused_breaking[k] : nullptr;
      return s;
    };
    if (neglecting && breaking_allowed)
      {
        TimerOutput::Scope t(timer, "damage");
        neglect_damaged_points();
      }
    if (!broken.empty() && breaking_allowed)
      {
        TimerOutput::Scope t(timer, "damage");
        for (unsigned int k = 0; k < blocks.size(); ++k)
          if (!fused[k])
            damage_updates += damage_pass(blocks[k].damage.get(), stretch_limits, k, state, blocks[k].points, arrays());
      }
    {
      TimerOutput::Scope t(timer, "force");
      for (unsigned int k = 0; k < blocks.size(); ++k)
        if (!blocks[k].rigid)
          blocks[k].material->compute_stage(fused_state(k), blocks[k].points);
    }
    if (has_stage_fields)
      {
        TimerOutput::Scope t(timer, "ghost exchange");
        fields->update_ghost_values(FieldUse::stage);
      }
    {
      TimerOutput::Scope t(timer, "force");
      for (unsigned int k = 0; k < blocks.size(); ++k)
        if (!blocks[k].rigid)
          blocks[k].material->compute_force(fused_state(k), blocks[k].continuum && discretization.force_blending ?
                                                              read_points[k] :
                                                              blocks[k].points);
    }
    for (auto &b : fused_breaking)
      {
        damage_updates += b.newly_broken;
        b.newly_broken = 0;
      }
    if (contact)
      contact->add_forces(mechanical.displacement, mechanical.velocity, broken.empty() ? nullptr : broken.data(),
                          damage_updates, mechanical.force.begin(), time, dt);
    if (!body_force->empty())
      for (unsigned int k = 0; k < dim * n; ++k)
        mechanical.force.local_element(k) += (*body_force)[k];
    // After contact and loads, before the coupling (a rigid point is no virtual point).
    rigid.apply(mechanical.force.begin(), mechanical.displacement.begin(), mechanical.velocity.begin());
    if (coupling)
      {
        // The virtual points' forces go to the FE nodes (Pi^T), action = reaction.
        TimerOutput::Scope t(timer, "continuum");
        coupling->transfer_forces(cloud, mechanical.force);
      }
  }

  double
  ForceModel::stable_time_step()
  {
    ModelState state{cloud, bonds, nullptr, mechanical.displacement.begin(), mechanical.force.begin(), nullptr, *fields};
    double     local = std::numeric_limits<double>::max();
    const std::vector<unsigned int> source = keeping_steps ? carried_step_sources() : std::vector<unsigned int>();
    std::vector<double>             steps(keeping_steps ? cloud.n_owned() : 0, std::numeric_limits<double>::max());
    double                          carried = 0;
    unsigned int                    differ  = 0;
    // Constants each within double's range can still overflow in the force
    // law (K / horizon^4, sqrt(K / rho)): refuse them here, naming them,
    // before they surface as a blow-up blamed on the loading.
    std::vector<unsigned int> bad(blocks.size(), 0);
    for (unsigned int k = 0; k < blocks.size(); ++k)
      {
        const Block &b = blocks[k];
        // Virtual points carry no mass (the FE nodes do); rigid points no stiffness (only contact).
        if (!b.points.empty() && !b.continuum && !b.rigid)
          {
            const double dt_block = keeping_steps ? block_step_by_point(state, b, source, steps, carried, differ) :
                                                    b.material->stable_time_step(state, b.points);
            // The largest double: no point of the block has any stiffness.
            // (With contact its points may be particles without bonds.)
            bad[k] = !(dt_block > 0 && (dt_block < std::numeric_limits<double>::max() || contact));
            local                 = std::min(local, dt_block);
          }
      }
    Utilities::MPI::max(bad, comm, bad);
    if (keeping_steps)
      {
        point_step = std::move(steps);
        differ     = Utilities::MPI::sum(differ, comm);
        AssertThrow(differ == 0,
                    ExcMessage("Adaptivity/Check kept families: the stable step carried over through a conversion "
                               "differs from a new one at " + std::to_string(differ) +
                               " points: a point's step reads more than its own and its neighbors' families"));
        double evaluated = 0;
        for (const auto &b : blocks)
          if (!b.continuum && !b.rigid)
            evaluated += b.points.size();
        n_carried_steps = Utilities::MPI::sum(carried, comm);
        n_point_steps   = Utilities::MPI::sum(evaluated, comm) - n_carried_steps;
      }
    const double fe = coupling ? coupling->continuum.stable_time_step() : std::numeric_limits<double>::max();
    for (unsigned int k = 0; k < blocks.size(); ++k)
      {
        const Block &b = blocks[k];
        // (Once every FE cell has converted there is none.)
        AssertThrow(!bad[k] && (!b.continuum || (fe > 0 && (fe < std::numeric_limits<double>::max() ||
                                                            !discretization.converted.empty()))),
                    ExcMessage("Materials/" + b.material_name + ": in block '" + b.name + "' (horizon " +
                               sci(b.horizon) + ") its constants (Bulk modulus " + sci(b.material->bulk_modulus()) +
                               ", Shear modulus " + sci(b.material->shear_modulus()) + ", Density " +
                               sci(b.material->density()) + ") give no finite stable time step: the force law " +
                               "leaves the range of double (the micromodulus is about 18 K / (pi horizon^4)). " +
                               "Give the constants and lengths in units that keep them nearer to 1 (e.g. MPa, mm)"));
      }
    double pd = Utilities::MPI::min(local, comm);
    if (contact)
      {
        // A point in contact has the material's and the contact's stiffness
        // in its row: their squared frequencies add.
        const double dt_contact = contact->stable_time_step(time);
        if (dt_contact < std::numeric_limits<double>::max())
          pd = 1 / std::sqrt(1 / (pd * pd) + 1 / (dt_contact * dt_contact));
      }
    return coupling ? std::min(pd, fe) : pd;
  }

  std::vector<unsigned int>
  ForceModel::carried_step_sources() const
  {
    const PreviousFamilies *previous = discretization.previous_families;
    const unsigned int      n        = cloud.n_owned();
    std::vector<unsigned int> source(n, numbers::invalid_unsigned_int);
    if (previous == nullptr) // the set-up, a restart: no step from before
      return source;
    // A point's step sums over its family the neighbors' family sums
    // (micromodulus, weighted volume, dilatation coupling): it is the one
    // from before if its own family and its neighbors' are.
    const bool usable = !bonds.kept.empty() && !discretization.previous_point.empty() &&
                        point_step.size() == previous->order->size();
    VectorType kept(cloud.scalar_partitioner);
    for (unsigned int i = 0; i < n; ++i)
      kept.local_element(i) = usable && bonds.kept[i] ? 1.0 : 0.0;
    kept.update_ghost_values();
    for (unsigned int i = 0; i < n; ++i)
      {
        bool all = kept.local_element(i) != 0;
        for (std::size_t b = bonds.offsets[i]; all && b < bonds.offsets[i + 1]; ++b)
          all = kept.local_element(bonds.neighbor[b]) != 0;
        if (all) // (a kept family's point is unchanged: it has its index before)
          source[i] = discretization.previous_point[i];
      }
    return source;
  }

  double
  ForceModel::block_step_by_point(const ModelState &state, const Block &b, const std::vector<unsigned int> &source,
                                  std::vector<double> &steps, double &carried, unsigned int &differ) const
  {
    std::vector<unsigned int> one(1);
    double                    dt = std::numeric_limits<double>::max();
    for (const unsigned int i : b.points)
      {
        one[0] = i;
        if (source[i] != numbers::invalid_unsigned_int)
          {
            steps[i] = point_step[source[i]];
            ++carried;
            if (discretization.check_kept_families && b.material->stable_time_step(state, one) != steps[i])
              ++differ;
          }
        else
          steps[i] = b.material->stable_time_step(state, one);
        dt = std::min(dt, steps[i]);
      }
    return dt;
  }

  double
  ForceModel::point_damage(const unsigned int i) const
  {
    if (broken.empty())
      return 0.0;
    const bool by_d = continuous[cloud.block[i]]; // else by the broken flags
    double     all = 0, intact = 0;
    for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
      {
        // Over the point's own family (Bonds::family).
        const double V = cloud.volume[bonds.neighbor[b]] * bonds.fraction(b) * bonds.own(b);
        all += V;
        intact += (by_d ? 1 - damage[b] : 1 - broken[b]) * V;
      }
    return all > 0 ? 1 - intact / all : 0.0; // a particle without bonds (rigid, contact only) has none to lose
  }

  double
  ForceModel::point_stretch(const unsigned int i) const
  {
    double       largest = -std::numeric_limits<double>::max();
    const double *u = mechanical.displacement.begin();
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
  ForceModel::fastest_bonded_speed() const
  {
    // A point whose bonds are all broken (or that has none: a rigid or
    // contact-only particle) has no neighbours to outrun: it may fly at any
    // speed. Its family is looked at only if it is the fastest yet.
    double fastest = 0;
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      {
        const double *v = mechanical.velocity.begin() + dim * i;
        const double  s = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        if (s <= fastest || mechanical.mass_density[i] == 0)
          continue;
        bool bonded = broken.empty() && bonds.offsets[i + 1] > bonds.offsets[i]; // a particle without bonds: free
        for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1] && !bonded; ++b)
          bonded = !broken[b];
        if (bonded)
          fastest = s;
      }
    return std::sqrt(Utilities::MPI::max(fastest, comm));
  }

  double
  ForceModel::released_energy(DamageSnapshot &before)
  {
    // A point's energy density depends on its own family alone (Material),
    // so only the points with a bond whose damage changed are evaluated, by
    // their material with the damage before and now (the forces and energy
    // densities of now stay as they are).
    const unsigned int n = cloud.n_owned();
    for (auto &c : released_points)
      c.clear();
    released_points.resize(blocks.size());
    // A rank whose bonds did not change has nothing to scan.
    for (unsigned int i = 0; i < n && before.updates != damage_updates; ++i)
      {
        const std::size_t first = bonds.offsets[i], count = bonds.offsets[i + 1] - first;
        if (std::memcmp(broken.data() + first, before.broken.data() + first, count) != 0 ||
            (!damage.empty() && std::memcmp(damage.data() + first, before.damage.data() + first, count * sizeof(double)) != 0))
          released_points[cloud.block[i]].push_back(i);
      }
    released_force.resize(dim * n);
    released_density.resize(n);
    ModelState now{cloud, bonds, broken.data(), mechanical.displacement.begin(), released_force.data(),
                   released_density.data(), *fields};
    now.time = time;
    now.dt   = dt;
    double e = 0;
    for (unsigned int k = 0; k < blocks.size(); ++k)
      if (!released_points[k].empty() && !blocks[k].rigid)
        {
          // (No bond breaks in these evaluations: their states carry no breaking.)
          ModelState at_now = block_state(now, k), at_before = at_now;
          at_before.broken  = before.broken.data();
          at_before.damage  = continuous[k] ? before.damage.data() : nullptr;
          e += blocks[k].material->released_energy(at_before, at_now, released_points[k]);
        }
    // The snapshot becomes now's where it differed, so that a solver that
    // keeps it (Verlet) copies nothing whole before the next step.
    for (const auto &points : released_points)
      for (const unsigned int i : points)
        {
          const std::size_t first = bonds.offsets[i], count = bonds.offsets[i + 1] - first;
          std::memcpy(before.broken.data() + first, broken.data() + first, count);
          if (!damage.empty())
            std::memcpy(before.damage.data() + first, damage.data() + first, count * sizeof(double));
        }
    before.updates = damage_updates;
    return Utilities::MPI::sum(e, comm);
  }

  ModelState
  ForceModel::block_state(const ModelState &state, const unsigned int k) const
  {
    ModelState s = state;
    s.damage     = continuous[k] ? damage.data() : nullptr;
    s.time       = time;
    s.dt         = dt;
    s.thermal_strain = temperature_function ? thermal_strain.begin() : nullptr;
    return s;
  }

  void
  ForceModel::update_temperature()
  {
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      {
        const double dT = temperature_function->value(cloud.position(i), time, cloud.hash(i)) - reference_temperature;
        temperature_change.local_element(i) = dT;
        // Continuum blocks ignore the temperature (doc/thermal.md).
        const Material *material            = blocks[cloud.block[i]].material.get();
        thermal_strain.local_element(i)     = material ? material->thermal_expansion_coefficient() * dT : 0.0;
      }
    check_finite({temperature_function.get()}, comm);
    temperature_change.update_ghost_values();
    thermal_strain.update_ghost_values();
  }

  std::size_t
  ForceModel::break_bonds()
  {
    TimerOutput::Scope t(timer, "damage");
    mechanical.displacement.update_ghost_values();
    ModelState state{cloud, bonds, broken.data(), mechanical.displacement.begin(), mechanical.force.begin(), nullptr, *fields};
    state.time        = time;
    state.dt          = dt;
    std::size_t newly = 0;
    for (unsigned int k = 0; k < blocks.size(); ++k)
      newly += damage_pass(blocks[k].damage.get(), stretch_limits, k, state, blocks[k].points, arrays());
    damage_updates += newly;
    if (neglecting)
      {
        const std::size_t before = damage_updates;
        neglect_damaged_points();
        newly += damage_updates - before;
      }
    return Utilities::MPI::sum(newly, comm);
  }

  void
  ForceModel::restore_damage_state(const DamageState &from)
  {
    if (from.bonds.updates != damage_updates)
      {
        broken = from.bonds.broken;
        damage = from.bonds.damage;
        // A new count, never one an earlier snapshot was taken at: the
        // damage differs from every copy taken since from.
        ++damage_updates;
        n_neglected = from.n_neglected;
        if (from.neglect_current)
          neglect_checked = damage_updates;
      }
    if (neglecting)
      {
        neglected = from.neglected;
        neglected.update_ghost_values();
      }
  }

  void
  ForceModel::save(CheckpointWriter &out) const
  {
    out.section("force model");
    out.put(broken);
    out.put(damage);
    out.put(damage_updates);
    out.put(neglect_checked);
    out.put(n_neglected);
    out.put(neglecting);
    if (neglecting)
      out.put_owned(neglected);
    fields->save(out);
  }

  void
  ForceModel::load(CheckpointReader &in)
  {
    in.section("force model");
    const std::size_t n_broken = broken.size(), n_damage = damage.size();
    in.get(broken);
    in.get(damage);
    in.expect(broken.size() == n_broken && damage.size() == n_damage,
              "this rank has " + std::to_string(n_broken) + " bonds with damage, the checkpoint " +
                std::to_string(broken.size()));
    in.get(damage_updates);
    in.get(neglect_checked);
    in.get(n_neglected);
    in.expect(in.get<bool>() == neglecting, "neglecting damaged points differs");
    if (neglecting)
      {
        in.get_owned(neglected, "the neglected points");
        neglected.update_ghost_values();
      }
    fields->load(in);
  }

  void
  ForceModel::neglect_damaged_points()
  {
    // A point's damage changes only when a bond of its own breaks, so a rank
    // whose bonds did not change since the last check has nothing new.
    std::size_t found = 0;
    if (damage_updates != neglect_checked)
      for (const auto &block : blocks)
        if (block.damage && block.neglect_damage < 1)
          for (const unsigned int i : block.points)
            if (neglected.local_element(i) == 0 && point_damage(i) > block.neglect_damage)
              {
                neglected.local_element(i) = 1;
                ++found;
              }
    neglect_checked = damage_updates;
    if (Utilities::MPI::sum(found, comm) == 0)
      return;
    n_neglected += found;
    neglected.update_ghost_values();
    // Both owners of a bond see both ends' marks, so both halves break.
    std::size_t newly = 0;
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
        if (!broken[b] && (neglected.local_element(i) > 0 || neglected.local_element(bonds.neighbor[b]) > 0))
          {
            broken[b] = 1;
            if (!damage.empty())
              damage[b] = 1;
            ++newly;
          }
    // neglect_checked stays behind: the neighbors these bonds damaged are
    // checked at the next evaluation.
    damage_updates += newly;
  }
} // namespace perideal
