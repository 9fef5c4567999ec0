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

    /// A one-line description for the set-up report.
    virtual std::string
    describe() const = 0;
  };

  void
  declare_damage_model_entry(ParameterHandler &prm);
} // namespace perideal
