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

  double
  Material::released_energy(const ModelState &before, const ModelState &now, const std::vector<unsigned int> &points) const
  {
    const auto strain_energy = [&](const ModelState &state) {
      for (const unsigned int i : points)
        state.energy[i] = 0;
      compute_stage(state, points);
      compute_force(state, points);
      double e = 0;
      for (const unsigned int i : points)
        e += state.energy[i] * state.cloud.volume[i];
      return e;
    };
    const double energy_before = strain_energy(before);
    return energy_before - strain_energy(now);
  }
} // namespace perideal
