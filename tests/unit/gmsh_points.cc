// Discretization/Gmsh/Cells as points (include/perideal/geometry/gmsh_points.h):
// the volumes and centroids of the four element shapes against their exact
// values (mixed_elements.msh, written by hand: a hexahedron with a
// non-planar top face, which a split into tetrahedra gets wrong, a prism with
// a slanted top, a pyramid with its apex over a corner, a tetrahedron), with
// their physical groups and Scale; a Gmsh tetrahedral box (format 4.1) and a
// Gmsh mesh of hexahedra and prisms sum to their volumes and first moments
// per block; the cubes made of the points have the points' volume and centre.
#include <perideal/geometry/gmsh_points.h>
#include <perideal/geometry/point_cubes.h>

#include <deal.II/grid/tria.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

using namespace perideal;
using dealii::Point;

namespace
{
  int failures = 0;

  void
  expect(const bool ok, const std::string &what)
  {
    if (!ok)
      {
        ++failures;
        std::cerr << "FAILED: " << what << '\n';
      }
  }

  bool
  close(const double a, const double b, const double tol = 1e-14)
  {
    return std::abs(a - b) <= tol * std::max(1., std::abs(b));
  }

  bool
  close(const Point<dim> &a, const Point<dim> &b, const double tol = 1e-14)
  {
    return close(a[0], b[0], tol) && close(a[1], b[1], tol) && close(a[2], b[2], tol);
  }

  std::string
  str(const Point<dim> &p)
  {
    std::ostringstream o;
    o << std::setprecision(17) << p;
    return o.str();
  }

  // Per block: the volume and the first moment over the volume.
  std::map<unsigned int, std::pair<double, Point<dim>>>
  blocks(const std::vector<GmshCellPoint> &points)
  {
    std::map<unsigned int, std::pair<double, Point<dim>>> b;
    for (const auto &p : points)
      {
        b[p.point.block].first += p.point.volume;
        b[p.point.block].second += p.point.volume * p.point.x;
      }
    for (auto &[block, v] : b)
      v.second /= v.first;
    return b;
  }
} // namespace

int
main(int argc, char **argv)
{
  if (argc != 4)
    {
      std::cerr << "usage: unit_gmsh_points mixed_elements.msh box_tets.msh mixed_cells.msh\n";
      return 2;
    }

  // Element tag, block, exact volume and centroid: the hexahedron is the unit
  // cube with its node (1 1 1) raised to (1 1 2), the top face z = 1 + x y;
  // the prism's triangle (2 0), (3 0), (2 1) rises from z = 0 to z = 1 + y;
  // the pyramid's unit square base at x = 4 has its apex at (4 0 1); the
  // tetrahedron is the unit one at x = 6.
  struct Exact
  {
    long         tag;
    unsigned int block;
    double       volume;
    Point<dim>   centroid;
  };
  const std::vector<Exact> exact = {
    {3, 1, 1.25, Point<dim>(8. / 15, 8. / 15, 29. / 45)},
    {4, 2, 2. / 3, Point<dim>(2 + 5. / 16, 3. / 8, 11. / 16)},
    {5, 3, 1. / 3, Point<dim>(4.375, 0.375, 0.25)},
    {6, 4, 1. / 6, Point<dim>(6.25, 0.25, 0.25)}};
  for (const double scale : {1., 2.})
    {
      const auto points = gmsh_cells_as_points(argv[1], scale);
      expect(points.size() == exact.size(), "mixed_elements.msh: 4 points (the line and triangle skipped)");
      for (unsigned int i = 0; i < std::min(points.size(), exact.size()); ++i)
        {
          const auto &p = points[i];
          const auto &e = exact[i];
          const std::string what = "element " + std::to_string(e.tag) + " at Scale " + std::to_string(scale);
          expect(p.tag == e.tag && p.point.block == e.block, what + ": tag and block");
          expect(close(p.point.volume, e.volume * scale * scale * scale),
                 what + ": volume " + std::to_string(p.point.volume));
          expect(close(p.point.x, scale * e.centroid), what + ": centroid " + str(p.point.x));
        }
    }

  // A box of 200 tetrahedra (format 4.1): blocks 1 (x < 4) and 2.
  const auto box = gmsh_cells_as_points(argv[2], 1);
  const auto box_blocks = blocks(box);
  expect(box.size() == 200 && box_blocks.size() == 2, "box_tets.msh: 200 points in 2 blocks");
  expect(close(box_blocks.at(1).first, 64, 1e-13) && close(box_blocks.at(2).first, 64, 1e-13),
         "box_tets.msh: each block's volume is 64");
  expect(close(box_blocks.at(1).second, Point<dim>(2, 2, 2), 1e-13) &&
           close(box_blocks.at(2).second, Point<dim>(6, 2, 2), 1e-13),
         "box_tets.msh: each block's centroid is its box's: " + str(box_blocks.at(1).second) + ", " +
           str(box_blocks.at(2).second));

  // Gmsh's 4 hexahedra and 14 prisms of a 2 x 1 x 0.5 box.
  const auto mixed = blocks(gmsh_cells_as_points(argv[3], 1));
  expect(mixed.size() == 1 && close(mixed.at(1).first, 1, 1e-13) &&
           close(mixed.at(1).second, Point<dim>(1, 0.5, 0.25), 1e-13),
         "mixed_cells.msh: volume 1 and centroid (1 0.5 0.25)");

  // The cubes: one cell per point, of its volume, centred on it.
  dealii::Triangulation<dim> tria;
  std::vector<CloudPoint>    cloud;
  for (const auto &p : box)
    cloud.push_back(p.point);
  create_point_cubes(tria, cloud);
  double volume = 0;
  for (const auto &cell : tria.active_cell_iterators())
    {
      volume += cell->measure();
      bool found = false;
      for (const auto &p : cloud)
        found = found || (close(cell->center(), p.x) && close(cell->measure(), p.volume, 1e-12) &&
                          cell->material_id() == p.block);
      expect(found, "a cube centred at " + str(cell->center()) + " of a point of its volume and block");
    }
  expect(tria.n_active_cells() == 200 && close(volume, 128, 1e-12), "200 cubes of total volume 128");

  if (failures == 0)
    std::cout << "OK\n";
  return failures == 0 ? 0 : 1;
}
