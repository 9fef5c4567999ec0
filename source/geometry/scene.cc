#include <perideal/geometry/scene.h>

#include <deal.II/base/utilities.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>

#include <cmath>
#include <limits>
#include <fstream>

namespace perideal
{
  using namespace dealii;

  void
  Scene::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Type",
                      "Box",
                      Patterns::Selection("Box|Cylinder shell|Gmsh"),
                      "The geometry: a box of hexahedra, Peridigm's tensor product "
                      "cylinder shell, or a hexahedral Gmsh mesh. Each active cell of "
                      "a peridynamic block becomes one point at its centroid with the "
                      "cell's volume.");
    prm.declare_entry("Horizon",
                      "0",
                      Patterns::Double(0),
                      "The horizon of every block that does not set its own. Bonds "
                      "with |xi| <= horizon*(1+1e-9) are kept, so a neighbor at exactly "
                      "the horizon (e.g. 3.0*h) is never lost to round-off.");
    prm.declare_entry("Partial volumes", "false", Patterns::Bool(),
                      "true: a neighbor counts with the part of its cell inside the horizon sphere, "
                      "computed from the cells' real geometry (trilinear hexahedra), instead of all "
                      "or nothing by its centroid; bonds then also join points whose centroids lie "
                      "up to a cell radius beyond the horizon. Each bond takes the mean of its two "
                      "directions' fractions, so action equals reaction. Smooths the family sums' "
                      "jumps with delta/h (doc/verification.md); costs 4 bytes per bond, more bonds, "
                      "and set-up time.");
    prm.declare_entry("Periodic directions", "", Patterns::List(Patterns::Selection("x|y|z"), 0, 3),
                      "Directions in which the scene repeats, e.g. 'y, z': the mesh's two bounding "
                      "faces normal to each are one face, and a family near one continues through the "
                      "other (minimum-image bonds, no stored copies). The period is the bounding box's "
                      "length and must exceed twice the horizon (plus a cell radius with partial "
                      "volumes); the cells on the two faces must match (a box does). The displacement "
                      "is periodic: a plane wave, a unit cell of a lattice or a laminate, a slab taken "
                      "from an infinite plate. Not with continuum blocks.");
    prm.declare_entry("Refinement regions", "", Patterns::Anything(),
                      "Regions of Discretization/Regions, comma separated: the cells whose centroid lies "
                      "in the i-th are refined as often as the i-th entry of Refinement levels says "
                      "(p4est keeps neighbours within one level). The usual use: fine cells for the "
                      "peridynamic block along a crack path, cells twice as large for the continuum "
                      "cells next to it, coarse cells elsewhere (hanging nodes are constrained).");
    prm.declare_entry("Refinement levels", "", Patterns::List(Patterns::Integer(0, 6)),
                      "One entry per Refinement region.");
    prm.enter_subsection("Box");
    prm.declare_entry("Lower corner", "0,0,0", Patterns::List(Patterns::Double(), 3, 3), "x,y,z of the lower corner.");
    prm.declare_entry("Upper corner", "1,1,1", Patterns::List(Patterns::Double(), 3, 3), "x,y,z of the upper corner.");
    prm.declare_entry("Subdivisions", "10,10,10", Patterns::List(Patterns::Integer(1), 3, 3), "Cells along x, y and z.");
    prm.leave_subsection();
    prm.enter_subsection("Cylinder shell");
    prm.declare_entry("Inner radius", "0.020", Patterns::Double(0), "Inner radius.");
    prm.declare_entry("Outer radius", "0.025", Patterns::Double(0), "Outer radius.");
    prm.declare_entry("Length", "0.100", Patterns::Double(0), "Length along z.");
    prm.declare_entry("Center x", "0", Patterns::Double(), "x of the axis.");
    prm.declare_entry("Center y", "0", Patterns::Double(), "y of the axis.");
    prm.declare_entry("Z origin", "0", Patterns::Double(), "z of the bottom end.");
    prm.declare_entry("Radial cells", "5", Patterns::Integer(1), "Cells through the thickness (Peridigm's 'Number Points Radius').");
    prm.declare_entry("Circumferential cells", "0", Patterns::Integer(0), "Cells around; 0: the mid-radius circumference over the radial spacing, rounded down (as Peridigm).");
    prm.declare_entry("Axial cells", "0", Patterns::Integer(0), "Cells along z; 0: the length over the radial spacing, rounded.");
    prm.leave_subsection();
    prm.enter_subsection("Gmsh");
    prm.declare_entry("Mesh file", "", Patterns::Anything(), "A hexahedral .msh file (format 2.2 or 4.1, ASCII). Volume physical groups become material ids (blocks), surface physical groups boundary ids. A relative path is taken from the directory the run starts in.");
    prm.declare_entry("Scale", "1", Patterns::Double(0), "Factor applied to the mesh coordinates.");
    prm.leave_subsection();
  }

  void
  Scene::parse_parameters(ParameterHandler &prm)
  {
    type              = prm.get("Type");
    horizon           = prm.get_double("Horizon");
    partial_volumes   = prm.get_bool("Partial volumes");
    periodic          = {{false, false, false}};
    for (const std::string &d : Utilities::split_string_list(prm.get("Periodic directions"), ','))
      {
        const unsigned int k = d[0] - 'x';
        AssertThrow(!periodic[k], ExcMessage("Discretization/Periodic directions: '" + d + "' is given twice"));
        periodic[k] = true;
      }
    refinement_regions = Utilities::split_string_list(prm.get("Refinement regions"), ',');
    for (const int l : Utilities::string_to_int(Utilities::split_string_list(prm.get("Refinement levels"), ',')))
      refinement_levels.push_back(l);
    AssertThrow(refinement_regions.size() == refinement_levels.size(),
                ExcMessage("Discretization/Refinement levels: give one number per entry of Refinement regions"));
    prm.enter_subsection("Box");
    lower = get_point(prm, "Lower corner");
    upper = get_point(prm, "Upper corner");
    {
      const auto v = Utilities::string_to_int(
        Utilities::split_string_list(prm.get("Subdivisions"), ','));
      for (unsigned int d = 0; d < dim; ++d)
        subdivisions[d] = v[d];
    }
    prm.leave_subsection();
    prm.enter_subsection("Cylinder shell");
    inner_radius          = prm.get_double("Inner radius");
    outer_radius          = prm.get_double("Outer radius");
    length                = prm.get_double("Length");
    center_x              = prm.get_double("Center x");
    center_y              = prm.get_double("Center y");
    z_origin              = prm.get_double("Z origin");
    radial_cells          = prm.get_integer("Radial cells");
    circumferential_cells = prm.get_integer("Circumferential cells");
    axial_cells           = prm.get_integer("Axial cells");
    prm.leave_subsection();
    prm.enter_subsection("Gmsh");
    mesh_file = prm.get("Mesh file");
    scale     = prm.get_double("Scale");
    prm.leave_subsection();

    if (type == "Box")
      for (unsigned int d = 0; d < dim; ++d)
        AssertThrow(upper[d] > lower[d],
                    ExcMessage("Discretization/Box: the upper corner must be above "
                               "the lower corner in every coordinate"));
    if (type == "Cylinder shell")
      {
        AssertThrow(outer_radius > inner_radius && inner_radius > 0,
                    ExcMessage("Discretization/Cylinder shell: need 0 < Inner radius < Outer radius"));
        require_positive(length, "Discretization/Cylinder shell/Length");
        const double dr = (outer_radius - inner_radius) / radial_cells;
        if (circumferential_cells == 0)
          circumferential_cells = static_cast<unsigned int>(
            std::floor(M_PI * (inner_radius + outer_radius) / dr));
        if (axial_cells == 0)
          axial_cells = std::max<unsigned int>(1, std::lround(length / dr));
        AssertThrow(circumferential_cells >= 3,
                    ExcMessage("Discretization/Cylinder shell/Circumferential cells must be at least 3"));
      }
    if (type == "Gmsh")
      {
        AssertThrow(!mesh_file.empty(),
                    ExcMessage("Discretization/Gmsh/Mesh file is empty"));
        AssertThrow(std::ifstream(mesh_file).good(),
                    ExcMessage("Discretization/Gmsh/Mesh file: cannot open '" +
                               mesh_file + "'"));
      }
  }

  double
  Scene::typical_spacing() const
  {
    if (type == "Box")
      return std::min({(upper[0] - lower[0]) / subdivisions[0],
                       (upper[1] - lower[1]) / subdivisions[1],
                       (upper[2] - lower[2]) / subdivisions[2]});
    if (type == "Cylinder shell")
      return (outer_radius - inner_radius) / radial_cells;
    return 0;
  }

  namespace
  {
    unsigned int
    trailing_zeros(unsigned int n)
    {
      unsigned int k = 0;
      while (n % 2 == 0 && n > 1)
        n /= 2, ++k;
      return k;
    }

    void
    create_box(const Scene &s, parallel::distributed::Triangulation<dim> &tria)
    {
      // p4est keeps the coarse mesh on every rank: use the coarsest mesh that
      // refines to the requested subdivisions.
      unsigned int k = 6;
      for (unsigned int d = 0; d < dim; ++d)
        k = std::min(k, trailing_zeros(s.subdivisions[d]));
      std::vector<unsigned int> coarse(dim);
      for (unsigned int d = 0; d < dim; ++d)
        coarse[d] = s.subdivisions[d] >> k;
      GridGenerator::subdivided_hyper_rectangle(tria, coarse, s.lower, s.upper);
      tria.refine_global(k);
    }

    void
    create_cylinder_shell(const Scene &s,
                          parallel::distributed::Triangulation<dim> &tria)
    {
      const unsigned int nr = s.radial_cells, nt = s.circumferential_cells,
                         nz = s.axial_cells;
      std::vector<Point<dim>> vertices;
      vertices.reserve((nr + 1) * nt * (nz + 1));
      for (unsigned int k = 0; k <= nz; ++k)
        for (unsigned int j = 0; j < nt; ++j)
          for (unsigned int i = 0; i <= nr; ++i)
            {
              const double r = s.inner_radius +
                               (s.outer_radius - s.inner_radius) * i / nr;
              const double theta = 2 * M_PI * j / nt;
              vertices.emplace_back(s.center_x + r * std::cos(theta),
                                    s.center_y + r * std::sin(theta),
                                    s.z_origin + s.length * k / nz);
            }
      auto v = [&](unsigned int i, unsigned int j, unsigned int k) {
        return (k * nt + (j % nt)) * (nr + 1) + i;
      };
      std::vector<CellData<dim>> cells(nr * nt * nz);
      unsigned int               c = 0;
      for (unsigned int k = 0; k < nz; ++k)
        for (unsigned int j = 0; j < nt; ++j)
          for (unsigned int i = 0; i < nr; ++i, ++c)
            {
              // deal.II's lexicographic vertex order in (r, theta, z): a
              // right-handed frame, so every cell has positive volume.
              cells[c].vertices = {v(i, j, k),         v(i + 1, j, k),
                                   v(i, j + 1, k),     v(i + 1, j + 1, k),
                                   v(i, j, k + 1),     v(i + 1, j, k + 1),
                                   v(i, j + 1, k + 1), v(i + 1, j + 1, k + 1)};
              cells[c].material_id = 0;
            }
      tria.create_triangulation(vertices, cells, SubCellData());
    }
  } // namespace

  Periodicity
  Scene::periodicity(const parallel::distributed::Triangulation<dim> &tria) const
  {
    // Every rank holds the whole coarse mesh, and refinement stays inside it.
    Periodicity result;
    for (unsigned int d = 0; d < dim; ++d)
      if (periodic[d])
        {
          double low = std::numeric_limits<double>::max(), high = -low;
          for (const auto &cell : tria.cell_iterators_on_level(0))
            for (const unsigned int v : cell->vertex_indices())
              {
                low  = std::min(low, cell->vertex(v)[d]);
                high = std::max(high, cell->vertex(v)[d]);
              }
          result.set(d, low, high);
        }
    return result;
  }

  void
  Scene::create_triangulation(parallel::distributed::Triangulation<dim> &tria) const
  {
    if (type == "Box")
      create_box(*this, tria);
    else if (type == "Cylinder shell")
      create_cylinder_shell(*this, tria);
    else
      {
        GridIn<dim> grid_in;
        grid_in.attach_triangulation(tria);
        std::ifstream in(mesh_file);
        try
          {
            grid_in.read_msh(in);
          }
        catch (const ExceptionBase &e)
          {
            std::ostringstream msg;
            e.print_info(msg);
            AssertThrow(false,
                        ExcMessage("Discretization/Gmsh/Mesh file: cannot read '" +
                                   mesh_file + "' as a hexahedral Gmsh mesh: " +
                                   msg.str()));
          }
        if (scale != 1)
          GridTools::scale(scale, tria);
      }
  }
} // namespace perideal
