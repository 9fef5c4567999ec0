#include <perideal/material/field_store.h>
#include <perideal/output/checkpoint.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/index_set.h>

#include <algorithm>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    std::string
    use_name(const FieldUse use)
    {
      switch (use)
        {
          case FieldUse::constant:
            return "constant";
          case FieldUse::stage:
            return "stage";
          case FieldUse::local:
            return "local";
          case FieldUse::history:
            return "history";
        }
      return "";
    }
  } // namespace

  std::shared_ptr<const Utilities::MPI::Partitioner>
  FieldStore::partitioner(const unsigned int c)
  {
    if (c == 1)
      return cloud.scalar_partitioner;
    auto it = partitioners.find(c);
    if (it != partitioners.end())
      return it->second;
    // Point p's entries are c p .. c p + c - 1: the scalar partitioner's sets
    // stretched, so ghosts keep the point cloud's local order.
    const auto    &scalar = *cloud.scalar_partitioner;
    const IndexSet &owned = scalar.locally_owned_range(), &ghost = scalar.ghost_indices();
    IndexSet        owned_c(c * owned.size()), ghost_c(c * owned.size());
    for (auto range = owned.begin_intervals(); range != owned.end_intervals(); ++range)
      owned_c.add_range(c * *range->begin(), c * (range->last() + 1));
    for (auto range = ghost.begin_intervals(); range != ghost.end_intervals(); ++range)
      ghost_c.add_range(c * *range->begin(), c * (range->last() + 1));
    owned_c.compress();
    ghost_c.compress();
    const MPI_Comm comm = scalar.get_mpi_communicator();
    auto           made = owned.size() == 0 ? std::make_shared<Utilities::MPI::Partitioner>(owned_c, comm) :
                                              std::make_shared<Utilities::MPI::Partitioner>(owned_c, ghost_c, comm);
    return partitioners.emplace(c, made).first->second;
  }

  void
  FieldStore::declare(const PointField &field)
  {
    AssertThrow(field.components == 1 || field.components == 3 || field.components == 6 || field.components == 9,
                ExcMessage("field '" + field.name + "': " + std::to_string(field.components) +
                           " components per point; a field has 1, 3, 6 or 9"));
    AssertThrow(!field.dissipation || (field.use == FieldUse::history && field.components == 1),
                ExcMessage("field '" + field.name + "': a dissipation field is a scalar history field"));
    const auto it = fields.find(field.name);
    if (it != fields.end())
      {
        const PointField &had = it->second.spec;
        AssertThrow(had.use == field.use && had.components == field.components && had.dissipation == field.dissipation,
                    ExcMessage("two models declare the field '" + field.name + "' differently (" +
                               use_name(had.use) + ", " + std::to_string(had.components) + " components; " +
                               use_name(field.use) + ", " + std::to_string(field.components) +
                               "): one of them must rename it"));
        return;
      }
    Entry &e = fields[field.name];
    e.spec   = field;
    e.now.reinit(partitioner(field.components));
    if (field.use == FieldUse::history)
      e.old.reinit(e.now.get_partitioner());
  }

  void
  FieldStore::declare(const BondField &field, const std::size_t n_bonds)
  {
    BondEntry &e = bond_fields[field.name];
    e.now.assign(n_bonds, 0.0);
    e.old.assign(n_bonds, 0.0);
    e.rewritten = field.rewritten;
  }

  FieldStore::Entry &
  FieldStore::entry(const std::string &name)
  {
    const auto it = fields.find(name);
    AssertThrow(it != fields.end(),
                ExcMessage("the per-point field '" + name +
                           "' was not declared: a model lists the fields it uses in point_fields()"));
    return it->second;
  }

  const VectorType &
  FieldStore::old(const std::string &name) const
  {
    const auto it = fields.find(name);
    AssertThrow(it != fields.end() && it->second.spec.use == FieldUse::history,
                ExcMessage("'" + name + "' is not a declared history field"));
    return it->second.old;
  }

  double *
  FieldStore::bond(const std::string &name)
  {
    const auto it = bond_fields.find(name);
    AssertThrow(it != bond_fields.end(),
                ExcMessage("the per-bond field '" + name +
                           "' was not declared: a model lists the fields it uses in bond_fields()"));
    bonds_written = true;
    return it->second.now.data();
  }

  const double *
  FieldStore::bond_old(const std::string &name) const
  {
    const auto it = bond_fields.find(name);
    AssertThrow(it != bond_fields.end(), ExcMessage("'" + name + "' is not a declared per-bond field"));
    return it->second.old.data();
  }

  const double *
  FieldStore::bond_latest(const std::string &name) const
  {
    return bonds_written ? bond_fields.at(name).now.data() : bond_old(name);
  }

  unsigned int
  FieldStore::components(const std::string &name) const
  {
    const auto it = fields.find(name);
    return it == fields.end() ? 0 : it->second.spec.components;
  }

  void
  FieldStore::update_ghost_values(const FieldUse use)
  {
    for (auto &[name, e] : fields)
      if (e.spec.use == use)
        e.now.update_ghost_values();
  }

  void
  FieldStore::commit()
  {
    for (auto &[name, e] : fields)
      if (e.spec.use == FieldUse::history)
        e.old = e.now;
    for (auto &[name, e] : bond_fields)
      if (!e.rewritten)
        std::copy(e.now.begin(), e.now.end(), e.old.begin());
      else if (bonds_written)
        e.now.swap(e.old);
    bonds_written = false;
  }

  void
  FieldStore::save(CheckpointWriter &out) const
  {
    out.section("history fields");
    for (const auto &[name, e] : fields)
      if (e.spec.use == FieldUse::history)
        {
          out.put(name);
          out.put_owned(e.old);
        }
    out.put(std::string());
    for (const auto &[name, e] : bond_fields)
      {
        out.put(name);
        out.put(e.old);
      }
    out.put(std::string());
  }

  FieldStore::History
  FieldStore::history(const unsigned int n_owned, const std::size_t n_bonds) const
  {
    History h;
    for (const auto &[name, e] : fields)
      if (e.spec.use == FieldUse::history)
        h.point_width += e.spec.components;
    h.bond_width = bond_fields.size();
    h.points.resize(std::size_t(h.point_width) * n_owned);
    h.bonds.resize(h.bond_width * n_bonds);
    unsigned int offset = 0;
    for (const auto &[name, e] : fields)
      if (e.spec.use == FieldUse::history)
        {
          const unsigned int c = e.spec.components;
          for (unsigned int i = 0; i < n_owned; ++i)
            for (unsigned int k = 0; k < c; ++k)
              h.points[std::size_t(h.point_width) * i + offset + k] = e.old.local_element(c * i + k);
          offset += c;
        }
    unsigned int f = 0;
    for (const auto &[name, e] : bond_fields)
      {
        for (std::size_t b = 0; b < n_bonds; ++b)
          h.bonds[h.bond_width * b + f] = e.old[b];
        ++f;
      }
    return h;
  }

  void
  FieldStore::carry_history(const History &from, const std::vector<unsigned int> &old_point,
                            const std::vector<std::size_t> &old_bond)
  {
    unsigned int offset = 0;
    for (auto &[name, e] : fields)
      if (e.spec.use == FieldUse::history)
        {
          const unsigned int c = e.spec.components;
          for (unsigned int i = 0; i < old_point.size(); ++i)
            if (old_point[i] != numbers::invalid_unsigned_int)
              for (unsigned int k = 0; k < c; ++k)
                e.old.local_element(c * i + k) = from.points[std::size_t(from.point_width) * old_point[i] + offset + k];
          e.now = e.old;
          offset += c;
        }
    AssertThrow(offset == from.point_width && bond_fields.size() == from.bond_width, ExcInternalError());
    unsigned int f = 0;
    for (auto &[name, e] : bond_fields)
      {
        for (std::size_t b = 0; b < old_bond.size(); ++b)
          if (old_bond[b] != std::size_t(-1))
            e.old[b] = from.bonds[from.bond_width * old_bond[b] + f];
        e.now = e.old;
        ++f;
      }
    bonds_written = false;
  }

  void
  FieldStore::load(CheckpointReader &in)
  {
    in.section("history fields");
    for (auto &[name, e] : fields)
      if (e.spec.use == FieldUse::history)
        {
          std::string found;
          in.get(found);
          in.expect(found == name, "expected the history field '" + name + "', found '" + found + "'");
          in.get_owned(e.old, "the history field '" + name + "'");
          e.now = e.old;
        }
    in.expect(in.get<std::uint64_t>() == 0, "the checkpoint has more history fields than this run's models");
    for (auto &[name, e] : bond_fields)
      {
        std::string found;
        in.get(found);
        in.expect(found == name, "expected the bond field '" + name + "', found '" + found + "'");
        const std::size_t n = e.old.size();
        in.get(e.old);
        in.expect(e.old.size() == n, "the bond field '" + name + "' has " + std::to_string(n) +
                                       " bonds on this rank, " + std::to_string(e.old.size()) + " in the checkpoint");
        e.now = e.old;
      }
    in.expect(in.get<std::uint64_t>() == 0, "the checkpoint has more bond fields than this run's models");
    bonds_written = false;
  }

  bool
  FieldStore::tracks_dissipation() const
  {
    for (const auto &[name, e] : fields)
      if (e.spec.dissipation)
        return true;
    return false;
  }

  double
  FieldStore::dissipated_energy(const std::vector<double> &volume, const unsigned int n_owned) const
  {
    double sum = 0;
    for (const auto &[name, e] : fields)
      if (e.spec.dissipation)
        for (unsigned int i = 0; i < n_owned; ++i)
          sum += volume[i] * e.now.local_element(i);
    return sum;
  }

  std::size_t
  FieldStore::memory_consumption() const
  {
    std::size_t bytes = 0;
    for (const auto &[name, e] : fields)
      bytes += e.now.memory_consumption() + (e.spec.use == FieldUse::history ? e.old.memory_consumption() : 0);
    for (const auto &[name, e] : bond_fields)
      bytes += (e.now.capacity() + e.old.capacity()) * sizeof(double);
    return bytes;
  }
} // namespace perideal
