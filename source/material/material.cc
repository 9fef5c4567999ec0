#include <perideal/material/material.h>

namespace perideal
{
  void
  declare_material_model_entry(ParameterHandler &prm)
  {
    prm.declare_entry("Model",
                      "",
                      dealii::Patterns::Anything(),
                      "The material model: one of " +
                        Registry<Material>::instance().names(", ") + ".");
  }
} // namespace perideal
