// A first-order 3D element as one peridynamic point (element_point.h).
// Hexahedra, prisms and pyramids are integrated as trilinear hexahedra, the
// prism and the pyramid as hexahedra with collapsed vertices (a prism's
// triangle is a quadrilateral with two equal vertices, a pyramid's apex four):
// the same solid, and the 2 x 2 x 2 Gauss rule integrates its volume and first
// moments exactly (the Jacobian is of degree 2 in each reference direction,
// times the position of degree 3), so non-planar faces are no approximation.

#include <perideal/base/format.h>
#include <perideal/geometry/element_point.h>
#include <perideal/geometry/hexahedron.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/tensor.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    std::string
    point_string(const Point<dim> &p)
    {
      return '(' + sci(p[0], 6) + ' ' + sci(p[1], 6) + ' ' + sci(p[2], 6) + ')';
    }

    // det[a, b, c] = a . (b x c)
    double
    triple(const Tensor<1, dim> &a, const Tensor<1, dim> &b, const Tensor<1, dim> &c)
    {
      return a * cross_product_3d(b, c);
    }

    struct Integral
    {
      double     volume = 0;
      Point<dim> centroid;
      double     min_jacobian = std::numeric_limits<double>::infinity(); // at the Gauss points
    };

    // The trilinear map of @p v (deal.II's lexicographic order), integrated
    // exactly with 2 x 2 x 2 Gauss points.
    Integral
    integrate_hexahedron(const std::array<Point<dim>, 8> &v)
    {
      const double   g = 0.5 / std::sqrt(3.);
      Integral       result;
      Tensor<1, dim> moment;
      for (unsigned int q = 0; q < 8; ++q)
        {
          std::array<double, 3> t;
          for (unsigned int d = 0; d < dim; ++d)
            t[d] = 0.5 + (((q >> d) & 1) ? g : -g);
          Tensor<1, dim> x;
          for (unsigned int c = 0; c < 8; ++c)
            {
              double N = 1;
              for (unsigned int d = 0; d < dim; ++d)
                N *= ((c >> d) & 1) ? t[d] : 1 - t[d];
              x += N * v[c];
            }
          const double det    = hex_jacobian(v, t);
          result.min_jacobian = std::min(result.min_jacobian, det);
          result.volume += det / 8;
          moment += det / 8 * x;
        }
      result.centroid = Point<dim>(moment / result.volume);
      return result;
    }
  } // namespace

  std::string
  shape_name(const ElementShape shape)
  {
    switch (shape)
      {
        case ElementShape::tetrahedron: return "tetrahedron";
        case ElementShape::hexahedron: return "hexahedron";
        case ElementShape::prism: return "prism";
        case ElementShape::pyramid: return "pyramid";
      }
    return "";
  }

  unsigned int
  n_corners(const ElementShape shape)
  {
    switch (shape)
      {
        case ElementShape::tetrahedron: return 4;
        case ElementShape::hexahedron: return 8;
        case ElementShape::prism: return 6;
        case ElementShape::pyramid: return 5;
      }
    return 0;
  }

  CloudPoint
  element_as_point(const ElementShape             shape,
                   const std::vector<Point<dim>> &p,
                   const std::vector<long>       &node_numbers,
                   const std::string             &element,
                   const bool                     scaled,
                   const unsigned int             block)
  {
    const unsigned int n_nodes = n_corners(shape);
    // The Jacobian at the corners (of the three edges there, in the corner
    // order of element_point.h) and inside: of one sign, positive, in a
    // valid cell.
    Integral                  cell;
    std::vector<double>       corner;
    std::vector<unsigned int> corner_node; // its index in the element
    switch (shape)
      {
        case ElementShape::tetrahedron:
          corner            = {triple(p[1] - p[0], p[2] - p[0], p[3] - p[0])};
          corner_node       = {0};
          cell.volume       = corner[0] / 6;
          cell.centroid     = (p[0] + p[1] + p[2] + p[3]) / 4;
          cell.min_jacobian = corner[0];
          break;
        case ElementShape::hexahedron:
          {
            const std::array<Point<dim>, 8> v{{p[0], p[1], p[3], p[2], p[4], p[5], p[7], p[6]}};
            corner_node = {0, 1, 3, 2, 4, 5, 7, 6};
            for (unsigned int c = 0; c < 8; ++c)
              corner.push_back(hex_jacobian(v, {{double(c & 1), double((c >> 1) & 1), double(c >> 2)}}));
            cell = integrate_hexahedron(v);
            break;
          }
        case ElementShape::prism:
          for (unsigned int c = 0; c < 6; ++c)
            {
              const unsigned int b = c < 3 ? 0 : 3, i = c % 3; // c's triangle
              corner.push_back(triple(p[b + 1] - p[b], p[b + 2] - p[b], p[i + 3] - p[i]));
              corner_node.push_back(c);
            }
          cell = integrate_hexahedron({{p[0], p[1], p[2], p[2], p[3], p[4], p[5], p[5]}});
          break;
        case ElementShape::pyramid:
          {
            const std::array<Point<dim>, 8> v{{p[0], p[1], p[3], p[2], p[4], p[4], p[4], p[4]}};
            corner_node = {0, 1, 3, 2};
            for (unsigned int c = 0; c < 4; ++c) // the apex has no Jacobian
              corner.push_back(hex_jacobian(v, {{double(c & 1), double(c >> 1), 0.}}));
            cell = integrate_hexahedron(v);
            break;
          }
      }
    // Where the cell is, for the message: the mean of its nodes (its
    // centroid is not defined if its volume is 0).
    Point<dim> low = p[0], high = p[0], mean;
    for (const auto &x : p)
      {
        mean += x / n_nodes;
        for (unsigned int d = 0; d < dim; ++d)
          low[d] = std::min(low[d], x[d]), high[d] = std::max(high[d], x[d]);
      }
    const double size     = low.distance(high);
    const double zero     = 1e-12 * size * size * size;
    const auto   worst    = std::min_element(corner.begin(), corner.end());
    const double jacobian = std::min(*worst, cell.min_jacobian);
    AssertThrow(std::isfinite(cell.volume) && std::isfinite(size) && jacobian > zero,
                ExcMessage(element + " at " + point_string(mean) + " is flat, inverted or tangled: its volume is " +
                           sci(cell.volume, 6) + " and its Jacobian " + sci(jacobian, 6) +
                           (*worst <= cell.min_jacobian ?
                              " at its node " + std::to_string(node_numbers[corner_node[worst - corner.begin()]]) :
                              std::string(" inside")) +
                           (scaled ? " (after Scale)" : "") +
                           ", and both must be positive (or its nodes are numbered against the file format's "
                           "order): fix the mesh"));
    return {cell.centroid, cell.volume, block};
  }
} // namespace perideal
