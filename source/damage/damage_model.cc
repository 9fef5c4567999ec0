#include <perideal/damage/damage_model.h>

namespace perideal
{
  void
  declare_damage_model_entry(ParameterHandler &prm)
  {
    prm.declare_entry("Model",
                      "",
                      dealii::Patterns::Anything(),
                      "The damage model: one of " +
                        Registry<DamageModel>::instance().names(", ") + ".");
    prm.declare_entry("Critical damage to neglect material point",
                      "1",
                      dealii::Patterns::Double(),
                      "In (0, 1]: a point of a block with this model whose damage exceeds it loses all its "
                      "remaining bonds, on both sides, at the next evaluation that may break bonds, and "
                      "goes on as a free particle: no bond force, no say in its neighbors' forces (Peridigm's "
                      "key of the same name). 1: never.");
  }
} // namespace perideal
