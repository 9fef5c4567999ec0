#pragma once
// The per-point and per-bond state that models keep, by name: what a material
// or damage model declares (PointField, BondField) the core allocates, ghosts
// and commits, and never names itself.
//
// - constant: filled in Material::initialize(), ghosted once after set-up
//   (LPS: the weighted volume);
// - stage: computed in compute_stage() at every evaluation, ghosted before
//   compute_force() (LPS: its alpha);
// - local: computed at every evaluation for the owned points, never
//   exchanged (LPS: the dilatation, for output);
// - history: two copies, N (the last accepted step, old()) and NP1 (the trial
//   of the step being solved, get()). A model computes NP1 from N at every
//   evaluation, so Newton iterations and line searches may evaluate as often
//   as they like, and a trial state that is not accepted leaves nothing
//   behind: commit() (N = NP1) runs once per accepted step. History fields
//   are not ghosted.
// A point field has 1 (scalar), 3 (vector), 6 (symmetric 3x3: xx yy zz xy yz
// xz) or 9 (3x3, row-major) components per point: component k of local point
// i is local_element(components * i + k), ghosts included.

#include <perideal/discretization/point_cloud.h>

#include <deal.II/base/partitioner.h>
#include <deal.II/lac/la_parallel_vector.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace perideal
{
  class CheckpointWriter;
  class CheckpointReader;

  using VectorType = dealii::LinearAlgebra::distributed::Vector<double>;

  enum class FieldUse
  {
    constant,
    stage,
    local,
    history
  };

  /// A per-point field a model declares (Material::point_fields()).
  struct PointField
  {
    std::string  name;           // the store's key, e.g. "dilatation"
    FieldUse     use        = FieldUse::stage;
    unsigned int components = 1; // 1, 3, 6 or 9
    /// The name in Output/Variables (cell data of the field files, vectors
    /// and tensors as 3 or 9 components), empty if the field is internal.
    std::string output_name = "";
    /// A history scalar that holds the energy the model has dissipated per
    /// unit volume so far (plastic or viscous work): the postprocessing sums
    /// V_i D_i into the globals column material_dissipation and into the
    /// energy balance (FieldStore::dissipated_energy()).
    bool dissipation = false;
  };

  /// A per-bond history value (a plastic stretch, a damage variable), one
  /// double per bond, N and NP1 as a history point field.
  struct BondField
  {
    std::string name;
    /// True if the model writes NP1 of every bond of its points at every
    /// evaluation (computed from N, as Elastic plastic and Viscoelastic do):
    /// commit() then swaps N and NP1 instead of copying them, which saves a
    /// pass over 16 bytes per bond and field per step. NP1 holds stale values
    /// after the swap until the next evaluation writes it, so a model that
    /// writes only some bonds (a running maximum kept where it grows) must
    /// leave this false.
    bool rewritten = false;
  };

  class FieldStore
  {
  public:
    explicit FieldStore(const PointCloud &cloud)
      : cloud(cloud)
    {}

    /// Allocates a declared field (zero). Declaring a name again with the same
    /// use and components is allowed (several blocks of one model); anything
    /// else is an error naming both.
    void
    declare(const PointField &field);
    /// Allocates a per-bond history field of @p n_bonds entries (zero).
    void
    declare(const BondField &field, const std::size_t n_bonds);

    /// The field @p name (for a history field its NP1 copy); a name no
    /// model declared is an error.
    VectorType &
    get(const std::string &name)
    {
      return entry(name).now;
    }

    /// N, the last accepted step's copy of history field @p name.
    const VectorType &
    old(const std::string &name) const;

    /// Per-bond history field @p name: NP1 (writable) and N.
    double *
    bond(const std::string &name);
    const double *
    bond_old(const std::string &name) const;
    /// The latest values of per-bond history field @p name: NP1 if an
    /// evaluation wrote the bond fields since the last commit(), else N (what
    /// the last accepted step left, which a rewritten field's swap put
    /// there). For a reader between evaluations (a damage pass), which does
    /// not know whether the step was accepted yet.
    const double *
    bond_latest(const std::string &name) const;

    bool
    has(const std::string &name) const
    {
      return fields.count(name) > 0;
    }
    unsigned int
    components(const std::string &name) const;

    /// True if some declared field is a dissipation field (PointField::dissipation).
    bool
    tracks_dissipation() const;
    /// This rank's sum over its @p n_owned points of V_i D_i over every
    /// dissipation field (their NP1 copies: after commit(), the accepted step's).
    double
    dissipated_energy(const std::vector<double> &volume, const unsigned int n_owned) const;

    /// Makes the ghost entries of every field of @p use current. Collective.
    void
    update_ghost_values(const FieldUse use);

    /// The step is accepted: N = NP1 for every history field (a rewritten
    /// bond field: N and NP1 swapped, if an evaluation wrote it since the last
    /// commit).
    void
    commit();

    std::size_t
    memory_consumption() const;

    /// The committed history (N) of every history field, point and bond
    /// (checkpoint.h); load() sets NP1 = N, as after commit(). The other
    /// uses are recomputed or constant.
    void
    save(CheckpointWriter &out) const;
    void
    load(CheckpointReader &in);
    /// The committed history (N) of the owned points and their bonds as
    /// rows, which a conversion carries over (and a rebalance moves between
    /// ranks, a row with its point or bond): per point the components of
    /// every history point field, per bond every history bond field, fields
    /// in name order.
    struct History
    {
      unsigned int        point_width = 0, bond_width = 0; // doubles per row
      std::vector<double> points, bonds;
    };
    History
    history(const unsigned int n_owned, const std::size_t n_bonds) const;
    /// After a rebuild of the points and bonds (a conversion,
    /// adaptivity.h): every history field's committed values (N, and NP1 =
    /// N as after load()) of the points and bonds @p from holds. @p old_point
    /// gives per owned point its row in @p from (invalid: new, left zero),
    /// @p old_bond per bond its row (-1: new, left zero). The fields are
    /// this run's: the layout of history().
    void
    carry_history(const History &from, const std::vector<unsigned int> &old_point,
                  const std::vector<std::size_t> &old_bond);

  private:
    struct Entry
    {
      PointField spec;
      VectorType now, old; // old: history fields only
    };
    Entry &
    entry(const std::string &name);
    struct BondEntry
    {
      std::vector<double> now, old;
      bool                rewritten = false;
    };
    // Set by bond() (an evaluation wrote NP1), cleared by commit(): a commit
    // with no evaluation since the last one must not swap N back.
    bool bonds_written = false;

    /// The point partitioner with @p components entries per point.
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner>
    partitioner(const unsigned int components);

    const PointCloud                                                                     &cloud;
    std::map<std::string, Entry>                                                          fields;
    std::map<std::string, BondEntry>                                                      bond_fields;
    std::map<unsigned int, std::shared_ptr<const dealii::Utilities::MPI::Partitioner>> partitioners;
  };
} // namespace perideal
