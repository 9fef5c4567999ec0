// Discretization/Type = Gmsh: a hexahedral .msh file, checked cell by cell
// (gmsh_check.cc) before deal.II reads it, or a 2D quadrilateral one extruded
// into hexahedra (a thin body).
#include <perideal/geometry/gmsh_check.h>
#include <perideal/geometry/scene.h>

#include <deal.II/base/utilities.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>

#include <cmath>
#include <filesystem>
#include <fstream>
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
                          "a mesh of tetrahedra, prisms or pyramids, or a 2D mesh, stops with the counts; "
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
        prm.leave_subsection();
      }

      void
      parse_parameters(ParameterHandler &prm, const double) override
      {
        prm.enter_subsection("Gmsh");
        mesh_file = prm.get("Mesh file");
        scale     = prm.get_double("Scale");
        thickness = prm.get_double("Extrusion thickness");
        layers    = prm.get_integer("Extrusion layers");
        prm.leave_subsection();

        AssertThrow(!mesh_file.empty(), ExcMessage("Discretization/Gmsh/Mesh file is empty"));
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
                    ExcMessage("Discretization/Gmsh/Mesh file: cannot open '" + mesh_file + "'"));
      }

      void
      create_triangulation(parallel::distributed::Triangulation<dim> &tria) const override
      {
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

      std::string
      cells_key() const override
      {
        return "Discretization/Gmsh/Mesh file";
      }

    private:
      std::string  mesh_file;
      double       scale     = 1;
      double       thickness = 0; // > 0: a 2D mesh extruded along z
      unsigned int layers    = 1;
    };
  } // namespace

  PERIDEAL_REGISTER(SceneGeometry, GmshScene, "Gmsh", "a hexahedral Gmsh mesh.")
} // namespace perideal
