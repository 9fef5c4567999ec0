#include <perideal/material/material.h>

namespace perideal
{
  std::size_t
  FieldStore::memory_consumption() const
  {
    std::size_t bytes = 0;
    for (const auto &f : fields)
      bytes += f.second.memory_consumption();
    return bytes;
  }

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
