#include <perideal/geometry/gmsh_check.h>
#include <perideal/geometry/scene.h>

#include <deal.II/base/utilities.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <limits>
#include <fstream>
#include <sstream>

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
    prm.declare_entry("Mesh file", "", Patterns::Anything(), "A hexahedral .msh file (format 2.2 or 4.1, ASCII) of first-order hexahedra. "
                      "Other cells are refused, not converted (p4est and the refinement need hexahedra): "
                      "a mesh of tetrahedra, prisms or pyramids, or a 2D mesh, stops with the counts; "
                      "Gmsh makes any geometry all-hexahedral with Mesh.SubdivisionAlgorithm = 2, or use "
                      "Transfinite Volume / Extrude with Recombine. Invalid hexahedra (a Jacobian that is "
                      "zero or changes sign in the cell: twisted, folded or flat cells) stop with the "
                      "element and its place; cells numbered left-handed are fine. Volume physical groups become material ids (blocks), surface physical groups boundary ids. A relative path is taken from the directory the run starts in.");
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

    // Ranges where the values are read: finite, positive where a size, and a
    // scene whose coordinates, spacing and horizon fit in double (else the
    // mesh or the neighbor search would be blamed for an overflow).
    AssertThrow(std::isfinite(horizon),
                ExcMessage("Discretization/Horizon must be finite, got " + Utilities::to_string(horizon)));
    const auto resolvable = [this](const double coordinate, const double spacing) {
      // The spacing must stand well above the round-off of the coordinates
      // (1e-10 of them: points stay distinct far beyond the 1e-9 horizon
      // tolerances), and coordinate plus horizon must not overflow.
      return std::isfinite(std::abs(coordinate) + 2 * horizon) &&
             spacing > 1e-10 * std::abs(coordinate);
    };
    if (type == "Box")
      {
        const char *axis = "xyz";
        for (unsigned int d = 0; d < dim; ++d)
          AssertThrow(std::isfinite(lower[d]) && std::isfinite(upper[d]),
                      ExcMessage("Discretization/Box: Lower corner and Upper corner must be finite"));
        for (unsigned int d = 0; d < dim; ++d)
          AssertThrow(upper[d] > lower[d],
                      ExcMessage("Discretization/Box: the upper corner must be above "
                                 "the lower corner in every coordinate"));
        for (unsigned int d = 0; d < dim; ++d)
          {
            const double span = upper[d] - lower[d], spacing = span / subdivisions[d];
            AssertThrow(std::isfinite(span) && std::isfinite(span + 2 * horizon),
                        ExcMessage(std::string("Discretization/Box: the box's length along ") + axis[d] +
                                   " (Upper corner - Lower corner = " + Utilities::to_string(upper[d]) +
                                   " - " + Utilities::to_string(lower[d]) +
                                   ") plus the horizon overflows a double: give a smaller box"));
            AssertThrow(resolvable(std::max(std::abs(lower[d]), std::abs(upper[d])), spacing),
                        ExcMessage(std::string("Discretization/Box: the cell size along ") + axis[d] + " (" +
                                   Utilities::to_string(spacing) +
                                   ") is too small for the coordinates (Lower corner " +
                                   Utilities::to_string(lower[d]) + ", Upper corner " +
                                   Utilities::to_string(upper[d]) +
                                   "): points would not be told apart in double; move the box "
                                   "near the origin or use fewer Subdivisions"));
          }
      }
    if (type == "Cylinder shell")
      {
        for (const auto &[value, key] : std::vector<std::pair<double, std::string>>{
               {inner_radius, "Inner radius"}, {outer_radius, "Outer radius"}, {length, "Length"},
               {center_x, "Center x"}, {center_y, "Center y"}, {z_origin, "Z origin"}})
          AssertThrow(std::isfinite(value),
                      ExcMessage("Discretization/Cylinder shell/" + key + " must be finite, got " +
                                 Utilities::to_string(value)));
        require_positive(inner_radius, "Discretization/Cylinder shell/Inner radius");
        require_positive(outer_radius, "Discretization/Cylinder shell/Outer radius");
        AssertThrow(outer_radius > inner_radius && inner_radius > 0,
                    ExcMessage("Discretization/Cylinder shell: need 0 < Inner radius < Outer radius"));
        require_positive(length, "Discretization/Cylinder shell/Length");
        const double dr = (outer_radius - inner_radius) / radial_cells;
        const double reach = std::max(std::abs(center_x), std::abs(center_y)) + outer_radius;
        AssertThrow(resolvable(reach, dr) && resolvable(std::abs(z_origin) + length, dr),
                    ExcMessage("Discretization/Cylinder shell: the radial cell size (" +
                               Utilities::to_string(dr) + ") is too small for the coordinates (up to " +
                               Utilities::to_string(std::max(reach, std::abs(z_origin) + length)) +
                               "), or they overflow a double with the horizon: check Inner radius, "
                               "Outer radius, Length, Center x/y, Z origin and Radial cells"));
        // The derived cell counts must fit an unsigned int before they are cast.
        AssertThrow(circumferential_cells != 0 ||
                      M_PI * (inner_radius + outer_radius) / dr < std::numeric_limits<int>::max(),
                    ExcMessage("Discretization/Cylinder shell/Circumferential cells: the default "
                               "(mid-radius circumference over the radial spacing) is " +
                               Utilities::to_string(M_PI * (inner_radius + outer_radius) / dr) +
                               " cells: set it, or fewer Radial cells"));
        AssertThrow(axial_cells != 0 || length / dr < std::numeric_limits<int>::max(),
                    ExcMessage("Discretization/Cylinder shell/Axial cells: the default (length "
                               "over the radial spacing) is " + Utilities::to_string(length / dr) +
                               " cells: set it, or fewer Radial cells"));
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
        AssertThrow(std::isfinite(scale) && scale > 0,
                    ExcMessage("Discretization/Gmsh/Scale must be finite and positive, got " +
                               Utilities::to_string(scale)));
        // Not opened before its type is known: opening a FIFO blocks.
        std::error_code error;
        const auto      status = std::filesystem::status(mesh_file, error);
        AssertThrow(!std::filesystem::exists(status) || std::filesystem::is_regular_file(status),
                    ExcMessage("Discretization/Gmsh/Mesh file: '" + mesh_file +
                               "' is not a regular file (a directory, a FIFO or a device): "
                               "give the path of a .msh file"));
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

    /**
     * Periodic along @p d joins the mesh's faces on the planes x_d = low and
     * x_d = high: they must be copies of each other. The minimum-image bonds
     * do not look at faces, so a mesh without them (a Cylinder shell along x
     * or y) or with faces that do not match ran silently with bonds across
     * the gap. Compares the coarse faces' centres and areas on the two
     * planes (every rank holds the whole coarse mesh: all decide alike).
     */
    void
    check_periodic_faces(const parallel::distributed::Triangulation<dim> &tria,
                         const unsigned int                                d,
                         const double                                      low,
                         const double                                      high)
    {
      const char   axis = char('x' + d);
      const double size = (high - low) + 1e-300;
      double       diameter = 0;
      for (const auto &cell : tria.cell_iterators_on_level(0))
        diameter = std::max(diameter, cell->diameter());
      const double quantum = 1e-6 * std::max(diameter, size);
      // Per plane: the faces' centres in the other two coordinates, and areas.
      std::array<std::vector<std::array<long long, 3>>, 2> faces;
      std::array<std::vector<Point<dim>>, 2>               centres;
      for (const auto &cell : tria.cell_iterators_on_level(0))
        for (const unsigned int f : cell->face_indices())
          if (cell->at_boundary(f))
            {
              const auto face = cell->face(f);
              for (unsigned int side = 0; side < 2; ++side)
                {
                  const double plane = side == 0 ? low : high;
                  bool         on    = true;
                  for (const unsigned int v : face->vertex_indices())
                    on = on && std::abs(face->vertex(v)[d] - plane) <= 1e-8 * size;
                  if (!on)
                    continue;
                  const Point<dim>          c = face->center();
                  std::array<long long, 3> key{};
                  unsigned int              k = 0;
                  for (unsigned int e = 0; e < dim; ++e)
                    if (e != d)
                      key[k++] = std::llround(c[e] / quantum);
                  key[2] = std::llround(face->measure() / (quantum * std::max(diameter, size)));
                  faces[side].push_back(key);
                  centres[side].push_back(c);
                }
            }
      const auto where = [&](const unsigned int side) {
        std::ostringstream s;
        s << axis << " = " << (side == 0 ? low : high);
        return s.str();
      };
      for (unsigned int side = 0; side < 2; ++side)
        AssertThrow(!faces[side].empty(),
                    ExcMessage("Discretization/Periodic directions: '" + std::string(1, axis) +
                               "' joins the mesh's boundary faces on the planes " + where(0) + " and " +
                               where(1) + " (its bounding box), but no boundary face lies on " + where(side) +
                               ": the mesh is not bounded by planes normal to " + std::string(1, axis) +
                               " (a Cylinder shell is periodic along z only): remove '" + std::string(1, axis) +
                               "' from Periodic directions"));
      std::array<std::vector<std::array<long long, 3>>, 2> sorted = faces;
      for (auto &list : sorted)
        std::sort(list.begin(), list.end());
      if (sorted[0] == sorted[1])
        return;
      // The first face of either plane without a copy on the other.
      for (unsigned int side = 0; side < 2; ++side)
        for (unsigned int i = 0; i < faces[side].size(); ++i)
          if (!std::binary_search(sorted[1 - side].begin(), sorted[1 - side].end(), faces[side][i]))
            {
              std::ostringstream at;
              at << "(" << centres[side][i] << ")";
              AssertThrow(false,
                          ExcMessage("Discretization/Periodic directions: along " + std::string(1, axis) +
                                     " the mesh's faces on " + where(0) + " (" + std::to_string(faces[0].size()) +
                                     " faces) and on " + where(1) + " (" + std::to_string(faces[1].size()) +
                                     " faces) do not match: the face centred at " + at.str() + " on " +
                                     where(side) + " has no copy on " + where(1 - side) +
                                     ". A periodic direction needs the two faces to be translated copies "
                                     "(a box is; mesh a Gmsh geometry with 'Periodic Surface'), or remove '" +
                                     std::string(1, axis) + "' from Periodic directions"));
            }
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
          check_periodic_faces(tria, d, low, high);
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
        check_gmsh_cells(mesh_file, scale);
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
