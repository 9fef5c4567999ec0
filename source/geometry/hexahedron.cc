// The trilinear hexahedron's Jacobian and volume (hexahedron.h).

#include <perideal/geometry/hexahedron.h>

#include <deal.II/base/tensor.h>

#include <algorithm>
#include <cmath>
#include <limits>

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

  HexJacobians
  hex_jacobians(const std::array<Point<dim>, 8> &v)
  {
    Point<dim> low = v[0], high = v[0];
    for (const auto &p : v)
      for (unsigned int d = 0; d < dim; ++d)
        low[d] = std::min(low[d], p[d]), high[d] = std::max(high[d], p[d]);
    const double size = low.distance(high);
    const double zero = 1e-12 * size * size * size;
    const double g    = 0.5 / std::sqrt(3.);
    HexJacobians result;
    unsigned int positive = 0, negative = 0;
    for (unsigned int q = 0; q < 16; ++q)
      {
        const unsigned int    c = q % 8;
        std::array<double, 3> t;
        for (unsigned int d = 0; d < dim; ++d)
          t[d] = q < 8 ? ((c >> d) & 1) : 0.5 + (((c >> d) & 1) ? g : -g);
        const double det = hex_jacobian(v, t);
        (q < 8 ? result.corner[c] : result.volume) += (q < 8 ? det : det / 8);
        positive += det > zero;
        negative += det < -zero;
      }
    result.one_sign = std::isfinite(size) && (positive == 16 || negative == 16);
    return result;
  }

  bool
  hex_centroid(const std::array<Point<dim>, 8> &v, Point<dim> &centroid)
  {
    const double   g[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
    double         volume = 0, smallest = std::numeric_limits<double>::infinity(), largest = -smallest;
    Tensor<1, dim> moment; // relative to v[0], as the Jacobian
    for (unsigned int q = 0; q < 8; ++q)
      {
        const std::array<double, 3> t{{g[q & 1], g[(q >> 1) & 1], g[q >> 2]}};
        const double                det = hex_jacobian(v, t);
        Tensor<1, dim>              x;
        for (unsigned int c = 1; c < 8; ++c)
          {
            double N = 1;
            for (unsigned int d = 0; d < dim; ++d)
              N *= ((c >> d) & 1) ? t[d] : 1 - t[d];
            x += N * (v[c] - v[0]);
          }
        volume += det;
        moment += det * x;
        smallest = std::min(smallest, det);
        largest  = std::max(largest, det);
      }
    if (largest - smallest <= 1e-12 * std::abs(volume / 8))
      return false;
    centroid = v[0] + moment / volume;
    return true;
  }
} // namespace perideal
