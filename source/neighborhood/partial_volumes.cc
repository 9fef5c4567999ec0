#include <perideal/neighborhood/partial_volumes.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <tuple>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    // The trilinear map of the cell at reference point (a, b, c) in [0, 1]^3.
    Point<dim>
    map(const double *v, const double a, const double b, const double c)
    {
      Point<dim> x;
      for (unsigned int k = 0; k < 8; ++k)
        {
          const double w = ((k & 1) ? a : 1 - a) * ((k & 2) ? b : 1 - b) * ((k & 4) ? c : 1 - c);
          for (unsigned int d = 0; d < dim; ++d)
            x[d] += w * v[3 * k + d];
        }
      return x;
    }

    // The share of the unit cube {0 <= a_k <= 1} with p . a <= d: the plane
    // cut of a box in closed form, sum over the corners c of
    // (-1)^(ones in c) max(0, d - p . c)^3 / (6 p_1 p_2 p_3), after
    // reflecting the negative p_k. A p_k near 0 is raised to 1e-4 max|p|: the
    // share is continuous in p, so that costs at most ~1e-4.
    double
    cube_below_plane(double p[3], double d)
    {
      for (unsigned int k = 0; k < 3; ++k)
        if (p[k] < 0)
          {
            d -= p[k];
            p[k] = -p[k];
          }
      const double floor = 1e-4 * std::max({p[0], p[1], p[2]});
      for (unsigned int k = 0; k < 3; ++k)
        p[k] = std::max(p[k], floor);
      const double sum = p[0] + p[1] + p[2];
      if (d <= 0)
        return 0;
      if (d >= sum)
        return 1;
      double share = 0;
      for (unsigned int k = 0; k < 8; ++k)
        {
          const double rest = d - ((k & 1) ? p[0] : 0) - ((k & 2) ? p[1] : 0) - ((k & 4) ? p[2] : 0);
          if (rest > 0)
            share += ((__builtin_popcount(k) & 1) ? -1 : 1) * rest * rest * rest;
        }
      return std::clamp(share / (6 * p[0] * p[1] * p[2]), 0.0, 1.0);
    }

    // Volume of the reference box [lo, lo + size]^3 of the cell inside the
    // ball. A sub-cell wholly inside or outside by its bounding sphere is
    // taken whole or dropped; a cut one is bisected, and at the last level
    // taken as the parallelepiped of its Jacobian, cut by a plane normal to
    // the direction from the center, at the sphere's mean depth over it.
    double
    box_in_ball(const double *v, const double lo[3], const double size, const Point<dim> &center,
                const double radius, const unsigned int levels_left)
    {
      Point<dim> corner[8];
      for (unsigned int k = 0; k < 8; ++k)
        corner[k] = map(v, lo[0] + ((k & 1) ? size : 0), lo[1] + ((k & 2) ? size : 0), lo[2] + ((k & 4) ? size : 0));
      Point<dim> mid;
      for (unsigned int k = 0; k < 8; ++k)
        mid += 0.125 * corner[k];
      double reach = 0;
      for (unsigned int k = 0; k < 8; ++k)
        reach = std::max(reach, mid.distance(corner[k]));
      const double distance = mid.distance(center);
      if (distance - reach >= radius)
        return 0;

      // The sub-cell's volume: the Jacobian at its middle (exact for
      // parallelepipeds) times its reference volume.
      Tensor<1, dim> ja, jb, jc;
      for (unsigned int k = 0; k < 8; ++k)
        {
          const double sa = (k & 1) ? 1 : -1, sb = (k & 2) ? 1 : -1, sc = (k & 4) ? 1 : -1;
          ja += 0.25 * sa * corner[k];
          jb += 0.25 * sb * corner[k];
          jc += 0.25 * sc * corner[k];
        }
      const double volume = std::abs(ja * cross_product_3d(jb, jc));
      if (distance + reach <= radius)
        return volume;
      if (levels_left == 0)
        {
          if (distance == 0)
            return volume;
          // x = mid + ja (a - 1/2) + jb (b - 1/2) + jc (c - 1/2) is inside
          // the tangent half-space n . (x - center) <= radius.
          // The plane moves in by the sphere's mean sag over the sub-cell's
          // tangential extent, rho^2 / (2 radius) averaged: sum |j_t|^2 / (24 radius).
          const Tensor<1, dim> n    = (mid - center) / distance;
          double               p[3] = {n * ja, n * jb, n * jc};
          const double         sag =
            (ja.norm_square() + jb.norm_square() + jc.norm_square() - p[0] * p[0] - p[1] * p[1] - p[2] * p[2]) /
            (24 * radius);
          return volume * cube_below_plane(p, radius - sag - distance + 0.5 * (p[0] + p[1] + p[2]));
        }
      const double half = 0.5 * size;
      double       sum  = 0;
      for (unsigned int k = 0; k < 8; ++k)
        {
          const double sub[3] = {lo[0] + ((k & 1) ? half : 0), lo[1] + ((k & 2) ? half : 0),
                                 lo[2] + ((k & 4) ? half : 0)};
          sum += box_in_ball(v, sub, half, center, radius, levels_left - 1);
        }
      return sum;
    }

    // Cell shapes, for the cells that are centrally symmetric about their
    // point (parallelepipeds: a box lattice, most refined regions). Two such
    // cells of one shape are translates, and the point reflection through a
    // bond's middle maps C_j ∩ B(x_i) onto C_i ∩ B(x_j): one number serves
    // both directions, and it depends only on the shape, the horizon and the
    // offset x_j - x_i. Shapes and offsets are quantized to 2^-32 of the
    // largest cell radius and the volume is computed from the quantized
    // values, so it is a function of the quantized key alone: the same on
    // every rank and for both owners, and computed once per distinct offset.
    struct ShapeKey
    {
      std::array<std::int64_t, 24> q;
      bool
      operator<(const ShapeKey &o) const
      {
        return q < o.q;
      }
    };

    struct OffsetKey
    {
      unsigned int                shape;
      double                      horizon;
      std::array<std::int64_t, 3> q;
      bool
      operator<(const OffsetKey &o) const
      {
        return std::tie(shape, horizon, q) < std::tie(o.shape, o.horizon, o.q);
      }
    };
  } // namespace

  double
  volume_in_ball(const double *vertices, const Point<dim> &center, const double radius)
  {
    const double origin[3] = {0, 0, 0};
    return box_in_ball(vertices, origin, 1.0, center, radius, 3);
  }

  void
  compute_partial_volumes(const PointCloud &cloud, Bonds &bonds, const std::vector<double> &block_horizon)
  {
    AssertThrow(cloud.cell_vertices.size() == 24 * std::size_t(cloud.n_local()),
                ExcInternalError("partial volumes need the cell geometry of every local point"));
    const double *v       = cloud.cell_vertices.data();
    const double  quantum = std::ldexp(std::max(cloud.max_cell_radius, 1e-300), -32);
    const auto    quantize = [&](const double x) { return std::int64_t(std::llround(x / quantum)); };

    // The shape of every local point's cell (-1: not centrally symmetric).
    std::map<ShapeKey, unsigned int> shape_index;
    std::vector<ShapeKey>            shapes;
    std::vector<int>                 shape(cloud.n_local(), -1);
    for (unsigned int i = 0; i < cloud.n_local(); ++i)
      {
        ShapeKey key;
        bool     symmetric = true;
        for (unsigned int k = 0; k < 8; ++k)
          for (unsigned int d = 0; d < dim; ++d)
            {
              key.q[3 * k + d] = quantize(v[24 * i + 3 * k + d] - cloud.X[3 * i + d]);
              symmetric &= std::abs(v[24 * i + 3 * k + d] + v[24 * i + 3 * (7 - k) + d] - 2 * cloud.X[3 * i + d]) <=
                           1e-12 * cloud.max_cell_radius;
            }
        if (!symmetric)
          continue;
        const auto [it, added] = shape_index.emplace(key, shapes.size());
        if (added)
          shapes.push_back(key);
        shape[i] = it->second;
      }

    std::map<OffsetKey, double> known;
    const auto                  share_of_shape = [&](const OffsetKey &key) {
      const auto it = known.find(key);
      if (it != known.end())
        return it->second;
      double vertices[24];
      for (unsigned int k = 0; k < 24; ++k)
        vertices[k] = shapes[key.shape].q[k] * quantum;
      const Point<dim> center(key.q[0] * quantum, key.q[1] * quantum, key.q[2] * quantum);
      const double     share = volume_in_ball(vertices, center, key.horizon) /
                           std::abs(volume_in_ball(vertices, Point<dim>(), 4 * cloud.max_cell_radius));
      known.emplace(key, share);
      return share;
    };

    bonds.volume_fraction.resize(bonds.n_bonds());
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
        {
          const unsigned int j       = bonds.neighbor[b];
          const double       delta_i = block_horizon[cloud.block[i]], delta_j = block_horizon[cloud.block[j]];
          double             beta;
          if (delta_i == delta_j && shape[i] >= 0 && shape[i] == shape[j])
            {
              // C_j ∩ B(x_i): the ball's center seen from x_j, x_i - x_j, in
              // the orientation of the smaller key so both owners agree.
              const bool   forward = cloud.key[i] < cloud.key[j];
              const unsigned int first = forward ? i : j, other = forward ? j : i;
              OffsetKey key{unsigned(shape[i]), delta_i, {}};
              const auto e = cloud.bond_vector(other, first);
              for (unsigned int d = 0; d < dim; ++d)
                key.q[d] = quantize(e[d]);
              beta = share_of_shape(key);
            }
          else
            {
              // Each ball's center as seen from the other cell: across a
              // periodic face that is the image one period away.
              Point<dim> center_i = cloud.position(i), center_j = cloud.position(j);
              if (cloud.periodicity.any())
                {
                  const auto e = cloud.bond_vector(i, j);
                  center_i     = center_j - e;
                  center_j     = cloud.position(i) + e;
                }
              // Both owners add the same two numbers; a + b == b + a exactly.
              beta = 0.5 * (volume_in_ball(v + 24 * j, center_i, delta_i) / cloud.volume[j] +
                            volume_in_ball(v + 24 * i, center_j, delta_j) / cloud.volume[i]);
            }
          bonds.volume_fraction[b] = static_cast<float>(std::min(1.0, beta));
        }
    // beta_ij is the mean of both balls' shares, the same number for i->j
    // and j->i: every bond kept is one symmetric bond, in both families.
    bonds.family.clear();
    bonds.family.shrink_to_fit();
    bonds.keep_if_bond(cloud.n_owned(), [&](unsigned int, const std::size_t b) { return bonds.volume_fraction[b] > 0; });
  }
} // namespace perideal
