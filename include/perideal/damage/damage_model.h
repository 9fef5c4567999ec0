#pragma once
// The DamageModel interface: decides which bonds of a block's points break.
// Bond damage is 0 or 1 and irreversible; point damage, computed by the core
// for output, is 1 - sum_j (1-d_ij) V_j / sum_j V_j.
//
// Bond i->j and j->i are separate entries, each decided by its owner: a model
// must decide from data both owners have (positions of both points), so the
// two halves agree. A new model is one file in source/damage/ with
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

    /// Breaks bonds of @p points: sets broken[b] = 1. Returns how many broke.
    virtual std::size_t
    update(const ModelState &state, const std::vector<unsigned int> &points, std::uint8_t *broken) const = 0;

    /// s_c if the model breaks a bond exactly when its stretch exceeds s_c
    /// and decides nothing else; a material may then fuse the test into its
    /// force loop (Material::fuses_stretch_criterion()). 0 otherwise.
    virtual double
    critical_stretch() const
    {
      return 0;
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

  void
  declare_damage_model_entry(ParameterHandler &prm);
} // namespace perideal
