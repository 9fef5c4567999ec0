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
  }
} // namespace perideal
