#pragma once
// The geometry of a run: a scene geometry of Registry<SceneGeometry> chosen
// by Discretization/Type (Box, Cylinder shell, Gmsh: source/geometry/, one
// file each), created on a parallel::distributed::Triangulation. The
// material id of a cell is its block number in the mesh. Scene holds the
// keys every geometry shares (horizon, periodicity, refinement).

#include <perideal/base/input.h>
#include <perideal/base/registry.h>
#include <perideal/geometry/periodicity.h>

#include <deal.II/base/point.h>
#include <deal.II/distributed/tria.h>

#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace perideal
{
  /// The sets of cells a mesh file names (an Exodus mesh's node sets, side
  /// sets and element blocks), by name: each the sorted level-0 indices of
  /// its coarse cells (Triangulation::coarse_cell_id_to_coarse_cell_index()).
  struct MeshSets
  {
    std::map<std::string, std::vector<unsigned int>> node_sets, side_sets, element_blocks;
    /// Peridigm's point numbers (from 1) and their cells, sorted by number:
    /// the numbers a Peridigm deck's own node sets give, an Exodus mesh's
    /// element ids (its element map), a Text file's points in the order of
    /// its lines.
    std::vector<std::pair<long, unsigned int>> point_cells;
  };

  /// One way to make the coarse mesh: a plugin registered with
  /// PERIDEAL_REGISTER(SceneGeometry, Class, "Name", "doc"), whose static
  /// declare_parameters declares its keys in subsection Discretization/Name.
  class SceneGeometry
  {
  public:
    virtual ~SceneGeometry() = default;

    /// Reads and checks the keys of its subsection (it enters it) of
    /// Discretization; @p horizon for the range checks.
    virtual void
    parse_parameters(ParameterHandler &prm, const double horizon) = 0;

    virtual void
    create_triangulation(dealii::parallel::distributed::Triangulation<dim> &tria) const = 0;

    /// The scene as a lattice before it is made (the size check): cells and
    /// spacing per direction, coarse cells.
    struct Lattice
    {
      std::array<double, 3> cells{}, spacing{};
      double                coarse_cells = 0;
    };
    /// False if the size is known only from the mesh once made (a file).
    virtual bool
    lattice(Lattice &) const
    {
      return false;
    }

    /// The sets of cells the mesh file names, nullptr if it names none (a
    /// generated geometry): Regions of Type Node set, Side set, Element block.
    virtual const MeshSets *
    mesh_sets() const
    {
      return nullptr;
    }

    /// For a scene that numbers its points by position: how many points,
    /// and Peridigm's number (from 1) of the point whose cell centre is @p x
    /// (Box: PdQuickGrid's order, x fastest, then y, then z). 0 otherwise.
    virtual long
    n_numbered_points() const
    {
      return 0;
    }
    virtual long
    point_number(const dealii::Point<dim> &) const
    {
      return 0;
    }

    /// The keys that set the number of cells, named by the size check.
    virtual std::string
    cells_key() const = 0;

  protected:
    /// A spacing well above the round-off of @p coordinate (1e-10 of it:
    /// points stay distinct far beyond the 1e-9 horizon tolerances), and
    /// coordinate plus @p horizon without overflow.
    static bool
    resolvable(const double coordinate, const double spacing, const double horizon)
    {
      return std::isfinite(std::abs(coordinate) + 2 * horizon) && spacing > 1e-10 * std::abs(coordinate);
    }
  };

  class Scene
  {
  public:
    /// Declared inside subsection "Discretization": the shared keys and every
    /// registered geometry's subsection.
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm);

    void
    create_triangulation(dealii::parallel::distributed::Triangulation<dim> &tria) const
    {
      geometry->create_triangulation(tria);
    }

    /// The period box of the periodic directions: the coarse mesh's bounding box.
    Periodicity
    periodicity(const dealii::parallel::distributed::Triangulation<dim> &tria) const;

    std::string type;
    std::unique_ptr<SceneGeometry> geometry; // of type
    double      horizon         = 0;
    bool        partial_volumes = false; // neighbors count with their cell's share inside the horizon
    std::array<bool, 3> periodic{{false, false, false}}; // Periodic directions
    std::vector<std::string>  refinement_regions; // applied by the Simulation, which knows the regions
    std::vector<unsigned int> refinement_levels;
  };
} // namespace perideal
