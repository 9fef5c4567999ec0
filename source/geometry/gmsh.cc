// Discretization/Type = Gmsh: a hexahedral .msh file, checked cell by cell
// (gmsh_check.cc) before deal.II reads it, or a 2D quadrilateral one extruded
// into hexahedra (a thin body), or, with Cells as points, a 3D mesh of any
// first-order cells read as one point each (gmsh_points.cc).
#include <perideal/base/format.h>
#include <perideal/geometry/gmsh_check.h>
#include <perideal/geometry/gmsh_file.h>
#include <perideal/geometry/gmsh_points.h>
#include <perideal/geometry/scene.h>

#include <deal.II/base/utilities.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class GmshScene : public SceneGeometry
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Gmsh");
        prm.declare_entry("Mesh file", "", Patterns::Anything(), "A hexahedral .msh file (format 2.2 or 4.1, ASCII) of first-order hexahedra. "
                          "Other cells are refused, not converted (p4est and the refinement need hexahedra): "
                          "a mesh of tetrahedra, prisms or pyramids, or a 2D mesh, stops with the counts "
                          "(for peridynamic blocks, Cells as points reads such a mesh as points); "
                          "Gmsh makes any geometry all-hexahedral with Mesh.SubdivisionAlgorithm = 2, or use "
                          "Transfinite Volume / Extrude with Recombine. Invalid hexahedra (a Jacobian that is "
                          "zero or changes sign in the cell: twisted, folded or flat cells) stop with the "
                          "element and its place; cells numbered left-handed are fine. Volume physical groups become material ids (blocks), surface physical groups boundary ids. A relative path is taken from the directory the run starts in.");
        prm.declare_entry("Scale", "1", Patterns::Double(0), "Factor applied to the mesh coordinates.");
        prm.declare_entry("Extrusion thickness", "0", Patterns::Double(0),
                          "0: Mesh file is a 3D mesh. A thickness h > 0: Mesh file is a 2D mesh of first-order "
                          "quadrilaterals in the plane z = 0 (a thin body's section), extruded along z from 0 to h "
                          "(after Scale) in Extrusion layers layers of hexahedra, one point per cell. The "
                          "surface physical groups become the cells' material ids (blocks; Regions: Physical group "
                          "dimension = 3), the curve groups the boundary ids of the side faces (dimension 2); the "
                          "faces z = 0 and z = h get the next two free boundary ids.");
        prm.declare_entry("Extrusion layers", "1", Patterns::Integer(1),
                          "Extrusion thickness > 0: the layers of cells through the thickness.");
        prm.declare_entry(
          "Cells as points", "false", Patterns::Bool(),
          "false: Mesh file is a mesh of first-order hexahedra (or a 2D one extruded), whose cells are the "
          "mesh's. true: every first-order 3D element of Mesh file (tetrahedra, hexahedra, prisms and "
          "pyramids, in any mix; ASCII, format 2.2 or 4.1) becomes one peridynamic point, at the "
          "element's centroid and with its volume, computed exactly after Scale (volume-weighted, also for "
          "hexahedra, prisms and pyramids with non-planar faces), and made into a cube of that volume as a "
          "Text file point is: the way to use a tetrahedral or mixed mesh, which p4est cannot hold, for "
          "peridynamic blocks. The element's volume physical group is its block (material id: Blocks/*/"
          "Material ids, Regions of Type Physical group with dimension 3; 0 if it has none). Surfaces, "
          "curves and points of the file are skipped: surface physical groups give no boundary ids, so "
          "select boundaries with geometric regions (Box, Expression). Refused, naming the element's "
          "number: second-order elements (mesh with Mesh.ElementOrder = 1), elements whose volume or "
          "Jacobian is zero or negative (flat, inverted or tangled, or numbered against Gmsh's order), "
          "and a file without 3D elements. Not with Extrusion thickness > 0.");
        prm.leave_subsection();
      }

      void
      parse_parameters(ParameterHandler &prm, const double scene_horizon) override
      {
        prm.enter_subsection("Gmsh");
        mesh_file       = prm.get("Mesh file");
        scale           = prm.get_double("Scale");
        thickness       = prm.get_double("Extrusion thickness");
        layers          = prm.get_integer("Extrusion layers");
        cells_as_points = prm.get_bool("Cells as points");
        prm.leave_subsection();
        horizon = scene_horizon;

        AssertThrow(!mesh_file.empty(), ExcMessage("Discretization/Gmsh/Mesh file is empty"));
        AssertThrow(std::isfinite(scale) && scale > 0,
                    ExcMessage("Discretization/Gmsh/Scale must be finite and positive, got " +
                               Utilities::to_string(scale)));
        AssertThrow(!(cells_as_points && thickness > 0),
                    ExcMessage("Discretization/Gmsh: Cells as points reads the cells of a 3D mesh, and Extrusion "
                               "thickness extrudes a 2D mesh: set one of them"));
        // Not opened before its type is known: opening a FIFO blocks.
        std::error_code error;
        const auto      status = std::filesystem::status(mesh_file, error);
        AssertThrow(!std::filesystem::exists(status) || std::filesystem::is_regular_file(status),
                    ExcMessage("Discretization/Gmsh/Mesh file: '" + mesh_file +
                               "' is not a regular file (a directory, a FIFO or a device): "
                               "give the path of a .msh file"));
        AssertThrow(std::ifstream(mesh_file).good(),
                    ExcMessage("Discretization/Gmsh/Mesh file: cannot open '" + mesh_file + "'"));
      }

      void
      create_triangulation(parallel::distributed::Triangulation<dim> &tria) const override
      {
        if (cells_as_points)
          {
            std::vector<CloudPoint> points;
            for (const auto &[tag, p] : gmsh_cells_as_points(mesh_file, scale))
              {
                const double edge = std::cbrt(p.volume);
                for (unsigned int d = 0; d < dim; ++d)
                  AssertThrow(resolvable(std::abs(p.x[d]), edge, horizon),
                              ExcMessage("Discretization/Gmsh/Mesh file '" + mesh_file + "': element " +
                                         std::to_string(tag) + " is too small (volume^(1/3) = " + sci(edge, 6) +
                                         ") for its coordinates: points would not be told apart in double; "
                                         "move the body near the origin"));
                points.push_back(p);
              }
            create_point_cubes(tria, points);
            return;
          }
        check_gmsh_cells(mesh_file, scale, thickness > 0);
        std::ifstream in(mesh_file);
        try
          {
            if (thickness > 0)
              {
                Triangulation<2> section;
                GridIn<2>        grid_in;
                grid_in.attach_triangulation(section);
                grid_in.read_msh(in);
                if (scale != 1)
                  GridTools::scale(scale, section);
                Triangulation<dim> extruded;
                GridGenerator::extrude_triangulation(section, layers + 1, thickness, extruded);
                tria.copy_triangulation(extruded);
                return;
              }
            GridIn<dim> grid_in;
            grid_in.attach_triangulation(tria);
            grid_in.read_msh(in);
          }
        catch (const ExceptionBase &e)
          {
            std::ostringstream msg;
            e.print_info(msg);
            AssertThrow(false,
                        ExcMessage("Discretization/Gmsh/Mesh file: cannot read '" + mesh_file +
                                   "' as a " + (thickness > 0 ? "quadrilateral" : "hexahedral") +
                                   " Gmsh mesh: " + msg.str()));
          }
        if (scale != 1)
          GridTools::scale(scale, tria);
      }

      /// An extruded section is sized before it is made (extrusion layers
      /// can make any number of cells from a small file): its quadrilaterals
      /// times the layers, one coarse cell each; bonds counted along z only
      /// (a lower bound). A mesh read whole is sized once read.
      bool
      lattice(Lattice &l) const override
      {
        GmshMesh section;
        if (thickness <= 0 || !read_gmsh_file(mesh_file, section))
          return false;
        double quadrilaterals = 0;
        for (const GmshMesh::Element &e : section.elements)
          quadrilaterals += e.type == 3; // Gmsh's 4-node quadrilateral
        const double infinite = std::numeric_limits<double>::infinity();
        l.cells               = {{quadrilaterals, 1, double(layers)}};
        l.spacing             = {{infinite, infinite, thickness / layers}};
        l.coarse_cells        = quadrilaterals * layers;
        return true;
      }

      std::string
      cells_key() const override
      {
        return thickness > 0 ? "Discretization/Gmsh/Mesh file and Extrusion layers" : "Discretization/Gmsh/Mesh file";
      }

    private:
      std::string  mesh_file;
      double       scale           = 1;
      double       thickness       = 0; // > 0: a 2D mesh extruded along z
      unsigned int layers          = 1;
      bool         cells_as_points = false;
      double       horizon         = 0; // for the points' resolution check
    };
  } // namespace

  PERIDEAL_REGISTER(SceneGeometry, GmshScene, "Gmsh",
                    "a hexahedral Gmsh mesh (with Cells as points: any first-order 3D mesh, a point per cell).")
} // namespace perideal
