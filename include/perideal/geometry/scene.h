#pragma once
// The geometry of a run: a built-in scene (box, cylinder shell) or a Gmsh
// hexahedral mesh, created on a parallel::distributed::Triangulation. The
// material id of a cell is its block number in the mesh.

#include <perideal/base/input.h>
#include <perideal/geometry/periodicity.h>

#include <deal.II/base/point.h>
#include <deal.II/distributed/tria.h>

#include <array>
#include <string>

namespace perideal
{
  class Scene
  {
  public:
    /// Declared inside subsection "Discretization".
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    void
    create_triangulation(dealii::parallel::distributed::Triangulation<dim> &tria) const;

    /// The period box of the periodic directions: the coarse mesh's bounding box.
    Periodicity
    periodicity(const dealii::parallel::distributed::Triangulation<dim> &tria) const;

    /// A typical cell size, for messages and defaults.
    double
    typical_spacing() const;

    std::string type;
    double      horizon         = 0;
    bool        partial_volumes = false; // neighbors count with their cell's share inside the horizon
    std::array<bool, 3> periodic{{false, false, false}}; // Periodic directions
    std::vector<std::string>  refinement_regions; // applied by the Simulation, which knows the regions
    std::vector<unsigned int> refinement_levels;

    // Box
    dealii::Point<dim>          lower, upper;
    std::array<unsigned int, 3> subdivisions{};

    // Cylinder shell (Peridigm's TensorProductCylinderMeshGenerator)
    double       inner_radius = 0, outer_radius = 0, length = 0;
    double       center_x = 0, center_y = 0, z_origin = 0;
    unsigned int radial_cells = 0, circumferential_cells = 0, axial_cells = 0;

    // Gmsh
    std::string mesh_file;
    double      scale = 1;
  };
} // namespace perideal
