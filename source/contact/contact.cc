// Contact: the Contact section, the proximity search across ranks and its
// Verlet list, and the evaluation of the contact models (contact.h).

#include <perideal/base/best_point.h>
#include <perideal/base/format.h>
#include <perideal/contact/contact.h>
#include <perideal/discretization/point_cloud.h>

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

namespace perideal
{
  using namespace dealii;

  // ---------------------------------------------------------------- parameters

  void
  ContactParameters::declare_parameters(ParameterHandler &prm, const std::vector<std::string> &interaction_names)
  {
    prm.enter_subsection("Contact");
    prm.declare_entry("General contact model", "", Patterns::Anything(),
                      "Name of a contact model of Contact models/Names that acts between every two different "
                      "peridynamic blocks; empty: none.");
    prm.declare_entry("Self contact model", "", Patterns::Anything(),
                      "Name of a contact model that acts between the points of one peridynamic block that are "
                      "not bonded (fragments, the faces of a crack); empty: none.");
    prm.declare_entry("Search radius", "0", Patterns::Double(0),
                      "Pairs closer than this are kept in the contact list; it must exceed every contact radius "
                      "(the difference is the skin). 0: 1.5 times the largest contact radius. The list is rebuilt "
                      "before any evaluation at which a point has moved more than half the skin since the last "
                      "build, so no contact is missed whatever the skin; a larger skin rebuilds less often and "
                      "keeps more pairs.");
    prm.declare_entry("Search frequency", "0", Patterns::Integer(0),
                      "If positive, also rebuild the list every this many evaluations (Peridigm's key); 0: only "
                      "when points have moved (see Search radius).");
    declare_named_section(prm, "Interactions", "interactions: a pair of blocks in contact with a model of its own",
                          interaction_names, [&](const std::string &) {
                            prm.declare_entry("First block", "", Patterns::Anything(), "Name of a block.");
                            prm.declare_entry("Second block", "", Patterns::Anything(),
                                              "Name of a block (the same as First block: self contact of it).");
                            prm.declare_entry("Contact model", "", Patterns::Anything(),
                                              "Name of a contact model of Contact models/Names.");
                          });
    prm.leave_subsection();
  }

  void
  ContactParameters::parse_parameters(ParameterHandler &prm, const std::vector<std::string> &interaction_names,
                                      const std::vector<std::string> &block_names)
  {
    const auto check_model = [&](const std::string &key, const std::string &name) {
      AssertThrow(name.empty() || models.count(name),
                  ExcMessage(key + ": '" + name + "' is not defined in Contact models/Names"));
    };
    const auto check_block = [&](const std::string &key, const std::string &name) {
      AssertThrow(!name.empty(), ExcMessage(key + " is not set"));
      AssertThrow(std::find(block_names.begin(), block_names.end(), name) != block_names.end(),
                  ExcMessage(key + ": '" + name + "' is not defined in Blocks/Names"));
    };
    prm.enter_subsection("Contact");
    general          = Utilities::trim(prm.get("General contact model"));
    self             = Utilities::trim(prm.get("Self contact model"));
    search_radius    = prm.get_double("Search radius");
    search_frequency = prm.get_integer("Search frequency");
    check_model("Contact/General contact model", general);
    check_model("Contact/Self contact model", self);
    prm.enter_subsection("Interactions");
    for (const auto &name : interaction_names)
      {
        const std::string path = "Contact/Interactions/" + name;
        prm.enter_subsection(name);
        Interaction interaction{name, Utilities::trim(prm.get("First block")), Utilities::trim(prm.get("Second block")),
                                Utilities::trim(prm.get("Contact model"))};
        prm.leave_subsection();
        check_block(path + "/First block", interaction.first);
        check_block(path + "/Second block", interaction.second);
        AssertThrow(!interaction.model.empty(), ExcMessage(path + "/Contact model is not set"));
        check_model(path + "/Contact model", interaction.model);
        interactions.push_back(interaction);
      }
    prm.leave_subsection();
    prm.leave_subsection();
    if (search_radius > 0)
      for (const auto &[name, model] : models)
        AssertThrow(search_radius > model->contact_radius(),
                    ExcMessage("Contact/Search radius " + sci(search_radius) + " must exceed the contact radius " +
                               sci(model->contact_radius()) + " of Contact models/" + name +
                               " (the difference is the skin of the contact list)"));
  }

  // ---------------------------------------------------------------- set-up

  Contact::Contact(const ContactParameters &parameters, const std::vector<Block> &blocks, const PointCloud &cloud,
                   const Bonds &bonds, const MPI_Comm comm, TimerOutput &timer)
    : parameters(parameters)
    , blocks(blocks)
    , cloud(cloud)
    , bonds(bonds)
    , comm(comm)
    , timer(timer)
  {}

  void
  Contact::setup(const std::vector<double> &mass_density, const double point_spacing)
  {
    const unsigned int      n_blocks = blocks.size();
    std::map<std::string, int> index;
    for (const auto &[name, model] : parameters.models)
      {
        index[name] = models.size();
        models.push_back(model.get());
      }
    const auto block_index = [&](const std::string &name) {
      for (unsigned int b = 0; b < n_blocks; ++b)
        if (blocks[b].name == name)
          return b;
      return n_blocks;
    };
    model_of.assign(n_blocks * n_blocks, -1);
    for (unsigned int a = 0; a < n_blocks; ++a)
      for (unsigned int b = 0; b < n_blocks; ++b)
        {
          if (blocks[a].continuum || blocks[b].continuum)
            continue;
          const std::string &name = a == b ? parameters.self : parameters.general;
          if (!name.empty())
            model_of[a * n_blocks + b] = index.at(name);
        }
    for (const auto &interaction : parameters.interactions)
      {
        const unsigned int a = block_index(interaction.first), b = block_index(interaction.second);
        for (const unsigned int k : {a, b})
          AssertThrow(!blocks[k].continuum,
                      ExcMessage("Contact/Interactions/" + interaction.name + ": block '" + blocks[k].name +
                                 "' is a continuum block, which cannot be in contact: its finite element nodes "
                                 "carry no contact points (only peridynamic points do, doc/contact.md). Make the "
                                 "block Peridynamic where bodies touch, or leave it out of the contact"));
        model_of[a * n_blocks + b] = model_of[b * n_blocks + a] = index.at(interaction.model);
      }
    AssertThrow(!cloud.periodicity.any(),
                ExcMessage("Contact: a periodic scene cannot have contact yet (the contact search does not wrap "
                           "current positions around the period); remove the Contact interactions or the "
                           "periodicity"));
    takes_part.assign(n_blocks, 0);
    for (unsigned int a = 0; a < n_blocks; ++a)
      for (unsigned int b = 0; b < n_blocks; ++b)
        if (model_of[a * n_blocks + b] >= 0)
          takes_part[a] = 1;
    warn_radius_beyond_horizon();

    bool velocity_needed = false;
    for (const ContactModel *model : models)
      {
        largest_contact_radius = std::max(largest_contact_radius, model->contact_radius());
        counts_needed          = counts_needed || model->uses_contact_counts();
        velocity_needed        = velocity_needed || model->uses_velocity();
      }
    stride = velocity_needed ? 2 * dim : dim;
    radius  = parameters.search_radius > 0 ? parameters.search_radius : 1.5 * largest_contact_radius;
    skin    = radius - largest_contact_radius;
    spacing = point_spacing;

    const unsigned int n = cloud.n_owned();
    X.assign(cloud.X.begin(), cloud.X.begin() + dim * n);
    volume.assign(cloud.volume.begin(), cloud.volume.begin() + n);
    mass.resize(n);
    horizon.resize(n);
    block.assign(cloud.block.begin(), cloud.block.begin() + n);
    active.resize(n);
    for (unsigned int i = 0; i < n; ++i)
      {
        mass[i]    = mass_density[i] * volume[i];
        horizon[i] = blocks[block[i]].horizon;
        active[i]  = takes_part[block[i]] && mass[i] > 0;
      }
    u_at_build.assign(dim * n, 0.0);
    lists.resize(models.size());
  }

  void
  Contact::warn_radius_beyond_horizon()
  {
    // Per model, the smallest horizon of a block it acts on.
    const unsigned int  n_blocks = blocks.size();
    std::vector<int>    smallest(models.size(), -1);
    for (unsigned int a = 0; a < n_blocks; ++a)
      for (unsigned int b = 0; b < n_blocks; ++b)
        if (const int m = model_of[a * n_blocks + b]; m >= 0)
          for (const unsigned int k : {a, b})
            if (smallest[m] < 0 || blocks[k].horizon < blocks[smallest[m]].horizon)
              smallest[m] = k;
    for (const auto &[name, model] : parameters.models)
      {
        const auto m = std::find(models.begin(), models.end(), model.get()) - models.begin();
        if (smallest[m] >= 0 && model->contact_radius() > blocks[smallest[m]].horizon)
          setup_warnings.push_back("Contact models/" + name + "/Contact radius " + sci(model->contact_radius()) +
                                   " exceeds the horizon " + sci(blocks[smallest[m]].horizon) + " of block '" +
                                   blocks[smallest[m]].name + "': points repel farther apart than a point "
                                   "bonds (a contact radius is usually 0.5 to 1 point spacing)");
      }
  }

  // ---------------------------------------------------------------- search

  namespace
  {
    // What travels to another rank for one contact ghost: gid, X, volume,
    // mass, horizon, block.
    constexpr unsigned int record_size = 1 + dim + 4;

    /// Refuses a pair of blocks whose points coincide (BestPoint's tag: the
    /// two blocks' index pair), naming them and the place.
    void
    refuse_coincident(const BestPoint &pair, const std::vector<Block> &blocks)
    {
      if (!pair.found)
        return;
      const unsigned int n_blocks = blocks.size();
      const unsigned int code     = static_cast<unsigned int>(pair.tag);
      const Block       &a = blocks[code / n_blocks], &b = blocks[code % n_blocks];
      AssertThrow(false,
                  ExcMessage("Contact: blocks '" + a.name + "' and '" + b.name + "' have points in the same place (" +
                             pair.describe() + " and a point of '" + b.name + "'), unbonded: the contact "
                             "force of two points at distance 0 has no direction, so they would pass through "
                             "each other without a force. Move one block by a fraction of the point spacing "
                             "(the bodies should touch, not overlap), or take the pair out of the contact"));
    }
  } // namespace

  /// A cell list over points: bins of edge @p edge, found by sorting.
  struct Contact::CellList
  {
    double                     lower[3], edge;
    std::vector<std::uint64_t> key;   // sorted
    std::vector<unsigned int>  point; // in key order

    static std::uint64_t
    pack(const std::int64_t i, const std::int64_t j, const std::int64_t k)
    {
      return (std::uint64_t(i) << 42) | (std::uint64_t(j) << 21) | std::uint64_t(k);
    }
    std::int64_t
    bin(const double x, const unsigned int d) const
    {
      return std::int64_t(std::floor((x - lower[d]) / edge)) + 1; // >= 1: neighbors at -1 stay >= 0
    }
  };

  void
  Contact::build(const VectorType &u)
  {
    const double *U = u.begin();
    std::copy(U, U + dim * cloud.n_owned(), u_at_build.begin());
    const std::vector<types::global_dof_index> previous_ghosts = gather_contact_ghosts(U);
    // The same contact ghosts as before (the common case between rebuilds):
    // the partitioners stay. Collective decision: every rank builds anew or none.
    const bool same_ghosts = partitioner && Utilities::MPI::min(ghost_gid == previous_ghosts ? 1u : 0u, comm) == 1;
    if (!same_ghosts)
      make_partitioners();
    const std::vector<double> y = current_positions(U);
    find_pairs(y, sort_into_cells(y));
    ++builds;
    steps_since_build = 0;
    built             = true;
    scanned_version   = std::numeric_limits<std::size_t>::max();
  }

  std::vector<types::global_dof_index>
  Contact::gather_contact_ghosts(const double *U)
  {
    // Contact ghosts: the points of other ranks within the search radius of
    // this rank's current bounding box.
    const unsigned int n = cloud.n_owned();
    X.resize(dim * n);
    volume.resize(n);
    mass.resize(n);
    horizon.resize(n);
    block.resize(n);
    std::vector<types::global_dof_index> previous_ghosts = std::move(ghost_gid);
    ghost_gid.clear();
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
    if (n_ranks == 1)
      return previous_ghosts;
    const auto                                  boxes   = Utilities::MPI::all_gather(comm, bounding_box(U));
    const unsigned int                          my_rank = Utilities::MPI::this_mpi_process(comm);
    std::map<unsigned int, std::vector<double>> to_send;
    for (unsigned int r = 0; r < n_ranks; ++r)
      if (r != my_rank && boxes[r][0] <= boxes[r][dim])
        to_send[r] = ghost_records_near(boxes[r], U); // empty too: some_to_some needs no more
    const auto received = Utilities::MPI::some_to_some(comm, to_send);
    // The partitioner numbers ghosts in ascending global index.
    std::vector<const double *> records;
    for (const auto &entry : received)
      for (std::size_t r = 0; r < entry.second.size(); r += record_size)
        records.push_back(entry.second.data() + r);
    std::sort(records.begin(), records.end(), [](const double *a, const double *b) { return a[0] < b[0]; });
    for (const double *p : records)
      {
        ghost_gid.push_back(static_cast<types::global_dof_index>(p[0]));
        for (unsigned int d = 0; d < dim; ++d)
          X.push_back(p[1 + d]);
        volume.push_back(p[1 + dim]);
        mass.push_back(p[2 + dim]);
        horizon.push_back(p[3 + dim]);
        block.push_back(static_cast<unsigned short>(p[4 + dim]));
      }
    return previous_ghosts;
  }

  std::array<double, 2 * dim>
  Contact::bounding_box(const double *U) const
  {
    std::array<double, 2 * dim> box;
    for (unsigned int d = 0; d < dim; ++d)
      {
        box[d]       = std::numeric_limits<double>::max();
        box[dim + d] = -std::numeric_limits<double>::max();
      }
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      if (active[i])
        for (unsigned int d = 0; d < dim; ++d)
          {
            const double y = X[dim * i + d] + U[dim * i + d];
            box[d]         = std::min(box[d], y);
            box[dim + d]   = std::max(box[dim + d], y);
          }
    return box;
  }

  std::vector<double>
  Contact::ghost_records_near(const std::array<double, 2 * dim> &box, const double *U) const
  {
    std::vector<double> records;
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      {
        if (!active[i])
          continue;
        bool inside = true;
        for (unsigned int d = 0; d < dim && inside; ++d)
          {
            const double y = X[dim * i + d] + U[dim * i + d];
            inside         = y >= box[d] - radius && y <= box[dim + d] + radius;
          }
        if (!inside)
          continue;
        records.push_back(cloud.gid[i]);
        for (unsigned int d = 0; d < dim; ++d)
          records.push_back(X[dim * i + d]);
        records.push_back(volume[i]);
        records.push_back(mass[i]);
        records.push_back(horizon[i]);
        records.push_back(block[i]);
      }
    return records;
  }

  void
  Contact::make_partitioners()
  {
    const unsigned int            n        = cloud.n_owned();
    const types::global_dof_index n_global = cloud.n_global(), first = n > 0 ? cloud.gid[0] : 0;
    const unsigned int            w        = stride;
    IndexSet                      owned(w * n_global), ghost(w * n_global);
    owned.add_range(w * first, w * (first + n));
    std::vector<types::global_dof_index> entries;
    entries.reserve(w * ghost_gid.size());
    for (const auto g : ghost_gid)
      for (unsigned int c = 0; c < w; ++c)
        entries.push_back(w * g + c);
    ghost.add_indices(entries.begin(), entries.end());
    owned.compress();
    ghost.compress();
    partitioner = std::make_shared<Utilities::MPI::Partitioner>(owned, ghost, comm);
    uv.reinit(partitioner);
    if (!counts_needed)
      return;
    IndexSet owned_points(n_global), ghost_points(n_global);
    owned_points.add_range(first, first + n);
    ghost_points.add_indices(ghost_gid.begin(), ghost_gid.end());
    owned_points.compress();
    ghost_points.compress();
    count_partitioner = std::make_shared<Utilities::MPI::Partitioner>(owned_points, ghost_points, comm);
    counts.reinit(count_partitioner);
  }

  std::vector<double>
  Contact::current_positions(const double *U)
  {
    const unsigned int n = cloud.n_owned(), n_local = n + ghost_gid.size();
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int d = 0; d < dim; ++d)
        uv.local_element(stride * i + d) = U[dim * i + d];
    uv.update_ghost_values();
    std::vector<double> y(dim * n_local);
    for (unsigned int i = 0; i < n_local; ++i)
      for (unsigned int d = 0; d < dim; ++d)
        y[dim * i + d] = X[dim * i + d] + uv.local_element(stride * i + d);
    return y;
  }

  Contact::CellList
  Contact::sort_into_cells(const std::vector<double> &y) const
  {
    const unsigned int n = cloud.n_owned(), n_local = n + ghost_gid.size();
    const auto         takes = [&](const unsigned int i) { return i >= n || active[i]; };
    CellList           cells;
    for (unsigned int d = 0; d < dim; ++d)
      cells.lower[d] = std::numeric_limits<double>::max();
    double upper[3] = {-std::numeric_limits<double>::max(), -std::numeric_limits<double>::max(),
                       -std::numeric_limits<double>::max()};
    for (unsigned int i = 0; i < n_local; ++i)
      if (takes(i))
        for (unsigned int d = 0; d < dim; ++d)
          {
            cells.lower[d] = std::min(cells.lower[d], y[dim * i + d]);
            upper[d]       = std::max(upper[d], y[dim * i + d]);
          }
    // At most 2^20 bins per direction (fragments flown far apart coarsen them).
    double extent = 0;
    for (unsigned int d = 0; d < dim; ++d)
      extent = std::max(extent, upper[d] - cells.lower[d]);
    cells.edge = std::max(radius, extent / double(1 << 20));
    std::vector<std::pair<std::uint64_t, unsigned int>> keyed;
    for (unsigned int i = 0; i < n_local; ++i)
      if (takes(i))
        keyed.emplace_back(cells.pack(cells.bin(y[dim * i], 0), cells.bin(y[dim * i + 1], 1), cells.bin(y[dim * i + 2], 2)), i);
    std::sort(keyed.begin(), keyed.end());
    cells.key.resize(keyed.size());
    cells.point.resize(keyed.size());
    for (std::size_t k = 0; k < keyed.size(); ++k)
      {
        cells.key[k]   = keyed[k].first;
        cells.point[k] = keyed[k].second;
      }
    return cells;
  }

  void
  Contact::points_within(const unsigned int i, const std::vector<double> &y, const CellList &cells,
                         std::vector<unsigned int> &found) const
  {
    const unsigned int n_blocks = blocks.size();
    const double       r2       = radius * radius;
    found.clear();
    const std::int64_t b[3] = {cells.bin(y[dim * i], 0), cells.bin(y[dim * i + 1], 1), cells.bin(y[dim * i + 2], 2)};
    // z is the key's lowest field: the three bins along z are one run of keys.
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        {
          const auto first =
            std::lower_bound(cells.key.begin(), cells.key.end(), cells.pack(b[0] + dx, b[1] + dy, b[2] - 1));
          const auto last = std::upper_bound(first, cells.key.end(), cells.pack(b[0] + dx, b[1] + dy, b[2] + 1));
          for (auto it = first; it != last; ++it)
            {
              const unsigned int j = cells.point[it - cells.key.begin()];
              if (j == i || model_of[block[i] * n_blocks + block[j]] < 0)
                continue;
              double dist2 = 0;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  const double e = y[dim * j + d] - y[dim * i + d];
                  dist2 += e * e;
                }
              if (dist2 <= r2)
                found.push_back(j);
            }
        }
  }

  void
  Contact::find_pairs(const std::vector<double> &y, const CellList &cells)
  {
    const unsigned int n = cloud.n_owned();
    // The cloud's local index of a contact-local point (for the bond lookup):
    // owned points are the same, ghosts by global index among the cloud's
    // nonlocal ghosts (sorted by it); not there: bonded to no owned point.
    const auto cloud_index = [&](const unsigned int j) -> unsigned int {
      if (j < n)
        return j;
      const auto begin = cloud.gid.begin() + n, end = cloud.gid.end();
      const auto it    = std::lower_bound(begin, end, ghost_gid[j - n]);
      return it != end && *it == ghost_gid[j - n] ? static_cast<unsigned int>(it - cloud.gid.begin()) :
                                                    numbers::invalid_unsigned_int;
    };
    const auto global_id = [&](const unsigned int j) { return j < n ? cloud.gid[j] : ghost_gid[j - n]; };
    for (auto &list : lists)
      {
        list.first.clear();
        list.second.clear();
        list.bonded_first.clear();
        list.bonded_second.clear();
        list.bond.clear();
      }
    const unsigned int        n_blocks = blocks.size();
    std::vector<unsigned int> found;
    // Per cloud-local point: its bond from the point i at hand (marked over
    // i's family, unmarked after), so that a found pair finds its bond in
    // O(1) rather than by a scan of the family.
    constexpr std::size_t    no_bond = std::numeric_limits<std::size_t>::max();
    std::vector<std::size_t> bond_to(cloud.n_local(), no_bond);
    // Unbonded pairs at distance 0 at the start (the first build).
    BestPoint  coincident(BestPoint::Order::smallest);
    const auto same_place = [&](const unsigned int i, const unsigned int j) {
      bool same = true;
      for (unsigned int d = 0; d < dim; ++d)
        same = same && y[dim * i + d] == y[dim * j + d];
      return same;
    };
    for (unsigned int i = 0; i < n; ++i)
      {
        if (!active[i])
          continue;
        points_within(i, y, cells, found);
        // The same order on any number of ranks: by global index.
        std::sort(found.begin(), found.end(), [&](unsigned int a, unsigned int c) { return global_id(a) < global_id(c); });
        for (std::size_t k = bonds.offsets[i]; k < bonds.offsets[i + 1]; ++k)
          bond_to[bonds.neighbor[k]] = k;
        for (const unsigned int j : found)
          {
            PairList          &list = lists[model_of[block[i] * n_blocks + block[j]]];
            const unsigned int c    = cloud_index(j);
            const std::size_t  bond = c != numbers::invalid_unsigned_int ? bond_to[c] : no_bond;
            if (bond == no_bond)
              {
                list.first.push_back(i);
                list.second.push_back(j);
                if (builds == 0 && same_place(i, j))
                  coincident.consider(global_id(i), global_id(i), &y[dim * i], BestPoint::Kind::point,
                                      block[i] * n_blocks + block[j]);
              }
            else
              {
                list.bonded_first.push_back(i);
                list.bonded_second.push_back(j);
                list.bond.push_back(bond);
              }
          }
        for (std::size_t k = bonds.offsets[i]; k < bonds.offsets[i + 1]; ++k)
          bond_to[bonds.neighbor[k]] = no_bond;
      }
    if (builds == 0)
      refuse_coincident(coincident.global(comm), blocks);
  }

  std::size_t
  Contact::n_pairs() const
  {
    std::size_t total = 0;
    for (const auto &list : lists)
      total += list.first.size() + list.bonded_first.size();
    return total;
  }

  // ---------------------------------------------------------------- forces

  void
  Contact::add_forces(const VectorType &u, const VectorType &v, const std::uint8_t *broken,
                      const std::size_t broken_version, double *force, const double time, const double dt)
  {
    const unsigned int n = cloud.n_owned();
    const double      *U = u.begin(), *Vel = v.begin();
    {
      // Rebuild when a point has moved more than half the skin since the
      // last build (then no pair within a contact radius is missing from the
      // list), or by Search frequency. Also: the fastest point's step
      // relative to the contact radius.
      TimerOutput::Scope t(timer, "contact search");
      double             maxima[2] = {0, 0}; // largest squared displacement since the build, speed
      unsigned int       fastest   = numbers::invalid_unsigned_int;
      for (unsigned int i = 0; i < n; ++i)
        if (active[i])
          {
            double m2 = 0, v2 = 0;
            for (unsigned int d = 0; d < dim; ++d)
              {
                const double e = U[dim * i + d] - u_at_build[dim * i + d];
                m2 += e * e;
                v2 += Vel[dim * i + d] * Vel[dim * i + d];
              }
            maxima[0] = std::max(maxima[0], m2);
            if (v2 > maxima[1])
              maxima[1] = v2, fastest = i;
          }
      // One collective per step; the fastest point is named (a second one)
      // only the first time it moves more than half a contact radius.
      const double local_speed = maxima[1];
      Utilities::MPI::max(ArrayView<const double>(maxima, 2), comm, ArrayView<double>(maxima, 2));
      const bool due = parameters.search_frequency > 0 && steps_since_build >= parameters.search_frequency;
      if (!built || due || maxima[0] > 0.25 * skin * skin)
        build(u);
      ++steps_since_build;
      largest_step_fraction = std::sqrt(maxima[1]) * dt / largest_contact_radius;
      if (largest_step_fraction > 0.5 && fastest_description.empty())
        {
          BestPoint best;
          if (fastest != numbers::invalid_unsigned_int)
            best.consider(std::sqrt(local_speed) * dt / largest_contact_radius, cloud.gid[fastest],
                          &cloud.X[dim * fastest]);
          fastest_description = best.global(comm).describe();
        }
    }

    TimerOutput::Scope t(timer, "contact force");
    if (stride == dim)
      std::copy(U, U + dim * n, uv.begin());
    else
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int d = 0; d < dim; ++d)
          {
            uv.local_element(stride * i + d)       = U[dim * i + d];
            uv.local_element(stride * i + dim + d) = Vel[dim * i + d];
          }
    uv.update_ghost_values();
    // The bonded pairs whose bond is broken join the evaluation; bonds only
    // break, so the pairs found stay until the next build, and the list is
    // looked at again only when some bond of this rank has broken since.
    if (broken && broken_version != scanned_version)
      {
        for (PairList &list : lists)
          {
            list.broken_first.clear();
            list.broken_second.clear();
            for (std::size_t p = 0; p < list.bond.size(); ++p)
              if (broken[list.bond[p]])
                {
                  list.broken_first.push_back(list.bonded_first[p]);
                  list.broken_second.push_back(list.bonded_second[p]);
                }
          }
        scanned_version = broken_version;
      }
    ContactPoints points{X.data(), uv.begin(), stride, volume.data(), mass.data(), horizon.data(), time, dt};
    if (counts_needed)
      {
        counts = 0;
        for (unsigned int m = 0; m < models.size(); ++m)
          {
            const PairList &list = lists[m];
            const double    r_c  = models[m]->contact_radius();
            count_contacts(list.first.data(), list.second.data(), list.first.size(), r_c);
            count_contacts(list.broken_first.data(), list.broken_second.data(), list.broken_first.size(), r_c);
          }
        counts.update_ghost_values();
        points.contacts = counts.begin();
      }
    ContactOutput out{force};
    for (unsigned int m = 0; m < models.size(); ++m)
      {
        const PairList &list = lists[m];
        models[m]->compute_force(points, list.first.data(), list.second.data(), list.first.size(), out);
        models[m]->compute_force(points, list.broken_first.data(), list.broken_second.data(),
                                 list.broken_first.size(), out);
      }
    energy         = out.energy;
    friction_power = out.friction_power;
  }

  void
  Contact::count_contacts(const unsigned int *first, const unsigned int *second, const std::size_t n,
                          const double radius)
  {
    const double *uv_ = uv.begin();
    for (std::size_t p = 0; p < n; ++p)
      {
        const unsigned int i = first[p], j = second[p];
        double             r2 = 0;
        for (unsigned int d = 0; d < dim; ++d)
          {
            const double e = (X[dim * j + d] + uv_[stride * j + d]) - (X[dim * i + d] + uv_[stride * i + d]);
            r2 += e * e;
          }
        if (r2 < radius * radius)
          counts.local_element(i) += 1;
      }
  }

  double
  Contact::stable_time_step(const double time) const
  {
    // Point i's row of M^-1 K: sum_j k V_i V_j / (rho_i V_i) twice (diagonal
    // and off-diagonal of equal masses), with sum_j V_j at most the volume of
    // the ball the neighbors' cells fill: radius r_c + a cell (sqrt(3)/2 h).
    const unsigned int n_blocks = blocks.size();
    double             local    = std::numeric_limits<double>::max();
    for (unsigned int i = 0; i < active.size(); ++i)
      if (active[i])
        for (unsigned int b = 0; b < n_blocks; ++b)
          {
            const int m = model_of[block[i] * n_blocks + b];
            if (m < 0)
              continue;
            const double r    = models[m]->contact_radius() + 0.5 * std::sqrt(3.0) * spacing;
            const double ball = 4.0 / 3.0 * M_PI * r * r * r;
            const double k    = models[m]->stiffness(std::max(horizon[i], blocks[b].horizon), time);
            const double rho  = mass[i] / volume[i];
            if (k > 0)
              local = std::min(local, std::sqrt(2 * rho / (k * ball)));
          }
    return Utilities::MPI::min(local, comm);
  }
} // namespace perideal
