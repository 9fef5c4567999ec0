#pragma once
// The DamageModel interface: decides the bond damage d in [0, 1] of a block's
// points. Binary models (critical stretch) set d = 1 in the per-bond byte
// array `broken`; continuous models (continuous() true) set d in the per-bond
// double array the core allocates only for them, and mark broken = 1 where d
// reaches 1. Damage is irreversible: d never decreases. Point damage,
// computed by the core for output, is 1 - sum_j (1-d_ij) V_j / sum_j V_j.
//
// Bond i->j and j->i are separate entries, each decided by its owner: a model
// must decide from data both owners have (positions of both points, the
// bond's own history), so the two halves agree. Critical stretches are
// applied by the core with one rule across blocks (BondStretchLimits): a bond
// between blocks A and B breaks at the smaller critical stretch of those of A
// and B that have one. A bond between a block with a continuous model and
// another block is allowed only if both blocks take the same damage model
// (ForceModel::setup() refuses it otherwise), so each owner applies the same
// law. A new model is one file in source/damage/ with
// PERIDEAL_REGISTER(DamageModel, ClassName, "Name", "documentation").

#include <perideal/base/input.h>
#include <perideal/material/material.h>

namespace perideal
{
  class DamageModel
  {
  public:
    virtual ~DamageModel() = default;

    virtual void
    parse_parameters(ParameterHandler &prm, const std::string &path) = 0;

    /// Called once per block with its material and horizon.
    virtual void
    initialize(const Material &material, const double horizon) = 0;

    /// The per-point and per-bond fields this model keeps (field_store.h),
    /// allocated by the core as a material's: an energy-based or
    /// history-dependent law keeps its state there.
    virtual std::vector<PointField>
    point_fields() const
    {
      return {};
    }
    virtual std::vector<BondField>
    bond_fields() const
    {
      return {};
    }

    /// True if the model breaks bonds by their energy
    /// (Material::bond_energies()): the core then asks the block's material
    /// for it (Material::request_bond_energy()) before its fields are
    /// allocated.
    virtual bool
    uses_bond_energy() const
    {
      return false;
    }

    /// True if the model sets a continuous bond damage
    /// (BondDamageArrays::damage); the core then allocates it (8 bytes per
    /// bond) and the block's material scales each bond by 1 - d
    /// (Material::supports_continuous_damage()). False: binary, d in {0, 1}
    /// in BondDamageArrays::broken, nothing more allocated.
    virtual bool
    continuous() const
    {
      return false;
    }

    /// Updates the damage of the bonds of @p points at the current state.
    /// Binary: sets damage.broken[b] = 1 for bonds that break; returns how
    /// many broke. Continuous: sets damage.damage[b] = max(its value, the
    /// law's), so d never decreases, and damage.broken[b] = 1 where d
    /// reaches 1; returns how many bonds' d rose. Like breaking, this runs
    /// only on states the integrators keep (an explicit step's evaluation,
    /// an implicit step's converged solve; ForceModel::breaking_allowed),
    /// never inside a Newton iteration, so a law that follows the largest
    /// stretch so far needs no history of its own; one that needs more
    /// declares it in bond_fields().
    virtual std::size_t
    update(const ModelState &state, const std::vector<unsigned int> &points, const BondDamageArrays &damage) const = 0;

    /// True if the model breaks a bond exactly when its stretch exceeds
    /// critical_stretch(t) and decides nothing else. The core then applies it
    /// with one rule across blocks (BondStretchLimits), and a material may
    /// fuse the test into its force loop (Material::fuses_stretch_criterion());
    /// update() is not called for the block.
    virtual bool
    stretch_criterion() const
    {
      return false;
    }

    /// s_c > 0 at time @p t, for a stretch_criterion() model.
    virtual double
    critical_stretch(const double /*t*/) const
    {
      return 0;
    }

    /// The limit this model sets on the bonds from its block to another
    /// block at time @p t (a bond between blocks breaks at the smaller of
    /// its two blocks' values): critical_stretch() unless the model gives an
    /// interface a strength of its own (Interface aware).
    virtual double
    interface_critical_stretch(const double t) const
    {
      return critical_stretch(t);
    }

    /// True if critical_stretch() changes with time: the core then refreshes
    /// the limits before every evaluation that may break bonds.
    virtual bool
    time_dependent() const
    {
      return false;
    }

    /// True if the law depends on the block's horizon (a critical bond
    /// energy): two owners of a bond between blocks of different horizons
    /// would then decide by different values, and the core refuses such
    /// bonds.
    virtual bool
    horizon_dependent() const
    {
      return false;
    }

    /// A one-line description for the set-up report.
    virtual std::string
    describe() const = 0;
  };

  /// |y|^2 > stretch_squared_limit(s_c) |xi|^2 is the bond-break test, in
  /// squared lengths (no square root); one definition for every pass using it.
  inline double
  stretch_squared_limit(const double critical_stretch)
  {
    return (1 + critical_stretch) * (1 + critical_stretch);
  }

  /**
   * The critical stretch of every bond, across blocks too: a bond within
   * block A breaks for good when its stretch exceeds A's s_c, a bond between
   * blocks A and B when it exceeds the smaller of the values A and B set on
   * their interfaces (DamageModel::interface_critical_stretch(), their s_c
   * unless the model gives the interface its own) among those whose damage
   * model is a stretch criterion (DamageModel::stretch_criterion()). A block without
   * one does not protect its bonds to a block with one; a bond between two
   * blocks without one never breaks. The limit depends on the two blocks
   * only, and both owners test the same lengths (bond_vectors()), so i->j
   * and j->i break in the same evaluation.
   *
   * A block all of whose bonds share one limit (the common case: one s_c
   * everywhere) gets it as common_limit(), which a material may fuse into
   * its bond loop at no cost per bond; the others take update(), a pass that
   * looks the limit up per bond.
   */
  class BondStretchLimits
  {
  public:
    BondStretchLimits() = default;

    /// Finds which blocks the bonds of each of @p n_blocks blocks reach, on
    /// any rank; no bond breaks until set(). Collective.
    BondStretchLimits(const unsigned int n_blocks, const PointCloud &cloud, const Bonds &bonds, const MPI_Comm comm);

    /// The critical stretch of each block within it and to other blocks
    /// (0: none), e.g. at a new time. Not collective: what differs between
    /// ranks was found by the constructor.
    void
    set(const std::vector<double> &within, const std::vector<double> &across);

    /// (1 + s_c)^2 of every bond of block @p k's points if they share one
    /// (on every rank), else 0.
    double
    common_limit(const unsigned int k) const
    {
      return common.empty() ? 0.0 : common[k];
    }

    /// (1 + s_c)^2 of block @p k's bonds by the far end's block (+infinity:
    /// never), n_blocks values.
    const double *
    limits_of(const unsigned int k) const
    {
      return pair.data() + k * n_blocks;
    }

    /// True if some bond of block @p k's points may break.
    bool
    may_break(const unsigned int k) const
    {
      return !breaking.empty() && breaking[k];
    }

    /// Breaks the bonds of @p points stretched beyond their limit: the pass
    /// for a block without common_limit(). Returns how many broke.
    std::size_t
    update(const ModelState &state, const std::vector<unsigned int> &points, std::uint8_t *broken) const;

  private:
    unsigned int              n_blocks = 0;
    std::vector<unsigned int> reaches;  // by block pair a * n_blocks + b: a bond of a's points ends in b (any rank)
    std::vector<double>       pair;     // (1 + s_c)^2 by block pair a * n_blocks + b; +infinity: never
    std::vector<double>       common;   // by block
    std::vector<bool>         breaking; // by block
  };

  /// Breaks the bonds of @p points whose stretch exceeds @p critical_stretch:
  /// the update() of a stretch criterion with one s_c for every bond.
  std::size_t
  break_overstretched(const ModelState                &state,
                      const std::vector<unsigned int> &points,
                      const double                     critical_stretch,
                      std::uint8_t                    *broken);

  /// A stretch criterion (DamageModel::stretch_criterion()): a model gives
  /// its s_c(t) (and an interface value, if it has one of its own), the core
  /// applies it across blocks; update() is the pass of a block alone.
  class StretchCriterion : public DamageModel
  {
  public:
    std::size_t
    update(const ModelState &state, const std::vector<unsigned int> &points, const BondDamageArrays &damage) const override
    {
      return break_overstretched(state, points, critical_stretch(state.time), damage.broken);
    }

    bool
    stretch_criterion() const final
    {
      return true;
    }

    double
    critical_stretch(const double t) const override = 0;
  };

  /// The damage pass of block @p k outside a material's bond loop: its own
  /// model's update() if that is not a stretch criterion (@p model may be
  /// null), else @p limits' pass if some bond of the block may break.
  inline std::size_t
  damage_pass(const DamageModel               *model,
              const BondStretchLimits         &limits,
              const unsigned int               k,
              const ModelState                &state,
              const std::vector<unsigned int> &points,
              const BondDamageArrays          &damage)
  {
    if (model && !model->stretch_criterion())
      return model->update(state, points, damage);
    return limits.may_break(k) ? limits.update(state, points, damage.broken) : 0;
  }

  void
  declare_damage_model_entry(ParameterHandler &prm);
} // namespace perideal
