#include <perideal/material/ordinary_state.h>

#include <cmath>
#include <limits>

namespace perideal
{
  using namespace dealii;

  std::vector<PointField>
  OrdinaryState::constant_fields() const
  {
    return {{weighted_volume, FieldUse::constant},
            {kappa, FieldUse::constant},
            {alpha, FieldUse::constant},
            {coupling, FieldUse::constant}};
  }

  void
  OrdinaryState::initialize(const ModelState &state, const std::vector<unsigned int> &points, const double K,
                            const double G, const std::string &path, const std::string &model) const
  {
    AssertThrow(state.bonds.family.empty(),
                ExcMessage(path + ": the " + model + " model does not support blocks of different horizons bonded "
                                                     "to each other; give the blocks one horizon"));
    const double *V  = state.cloud.volume.data();
    VectorType   &m  = state.fields.get(weighted_volume);
    VectorType   &k  = state.fields.get(kappa);
    VectorType   &a  = state.fields.get(alpha);
    VectorType   &D  = state.fields.get(coupling);
    for (const unsigned int i : points)
      {
        double mi = 0, Ai = 0;
        for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
          {
            const unsigned int j  = state.bonds.neighbor[b];
            const double       r0 = state.cloud.bond_vector(i, j).norm();
            const double       w  = state.bonds.fraction(b);
            mi += w * r0 * r0 * V[j];
            Ai += w * r0 * V[j];
          }
        const double inverse = mi > 0 ? 1 / mi : 0.0;
        m.local_element(i)   = mi;
        k.local_element(i)   = 3 * K * inverse;
        a.local_element(i)   = 15 * G * inverse;
        D.local_element(i)   = std::abs(3 * K - 5 * G) * inverse * Ai * inverse;
      }
  }

  double
  OrdinaryState::stable_time_step(const ModelState &state, const std::vector<unsigned int> &points,
                                  const double rho) const
  {
    const double     *V  = state.cloud.volume.data();
    const VectorType &a  = state.fields.get(alpha);
    const VectorType &k  = state.fields.get(kappa);
    const VectorType &m  = state.fields.get(weighted_volume);
    const VectorType &D  = state.fields.get(coupling);
    double            dt = std::numeric_limits<double>::max();
    for (const unsigned int i : points)
      {
        double pair = 0, Ai = 0, neighbors = 0;
        for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
          {
            const unsigned int j  = state.bonds.neighbor[b];
            const double       r0 = state.cloud.bond_vector(i, j).norm();
            const double       w  = state.bonds.fraction(b);
            pair += (a.local_element(i) + a.local_element(j)) * w * V[j];
            Ai += w * r0 * V[j];
            neighbors += w * r0 * V[j] * D.local_element(j);
          }
        if (m.local_element(i) == 0)
          continue;
        const double gamma  = k.local_element(i) - a.local_element(i) / 3;
        const double lambda = (2 * pair + 6 * std::abs(gamma) * Ai * Ai / m.local_element(i) + 6 * neighbors) / rho;
        if (lambda > 0)
          dt = std::min(dt, 2 / std::sqrt(lambda));
      }
    return dt;
  }
} // namespace perideal
