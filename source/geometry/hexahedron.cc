// The trilinear hexahedron's Jacobian and volume (hexahedron.h).

#include <perideal/geometry/hexahedron.h>

#include <deal.II/base/tensor.h>

#include <cmath>

namespace perideal
{
  using namespace dealii;

  double
  hex_jacobian(const std::array<Point<dim>, 8> &v, const std::array<double, 3> &t)
  {
    Tensor<2, dim> J; // J[i][d] = dx_i / dxi_d
    for (unsigned int c = 1; c < 8; ++c) // relative to v[0], whose term is zero
      for (unsigned int d = 0; d < dim; ++d)
        {
          double dN = 1;
          for (unsigned int e = 0; e < dim; ++e)
            {
              const bool upper = (c >> e) & 1;
              if (e == d)
                dN *= upper ? 1 : -1;
              else
                dN *= upper ? t[e] : 1 - t[e];
            }
          for (unsigned int i = 0; i < dim; ++i)
            J[i][d] += (v[c][i] - v[0][i]) * dN;
        }
    return determinant(J);
  }

  double
  hex_volume(const std::array<Point<dim>, 8> &v)
  {
    const double g[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
    double       volume = 0;
    for (unsigned int q = 0; q < 8; ++q)
      volume += hex_jacobian(v, {{g[q & 1], g[(q >> 1) & 1], g[q >> 2]}});
    return volume / 8;
  }
} // namespace perideal
