// Discretization/Type = Cylinder shell: Peridigm's
// TensorProductCylinderMeshGenerator, a hollow cylinder along z of radial x
// circumferential x axial hexahedra.
#include <perideal/geometry/scene.h>

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class CylinderShell : public SceneGeometry
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
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
      }

      void
      parse_parameters(ParameterHandler &prm, const double horizon) override
      {
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
        const double dr    = (outer_radius - inner_radius) / radial_cells;
        const double reach = std::max(std::abs(center_x), std::abs(center_y)) + outer_radius;
        AssertThrow(resolvable(reach, dr, horizon) && resolvable(std::abs(z_origin) + length, dr, horizon),
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
          circumferential_cells =
            static_cast<unsigned int>(std::floor(M_PI * (inner_radius + outer_radius) / dr));
        if (axial_cells == 0)
          axial_cells = std::max<unsigned int>(1, std::lround(length / dr));
        AssertThrow(circumferential_cells >= 3,
                    ExcMessage("Discretization/Cylinder shell/Circumferential cells must be at least 3"));
      }

      void
      create_triangulation(parallel::distributed::Triangulation<dim> &tria) const override
      {
        const unsigned int      nr = radial_cells, nt = circumferential_cells, nz = axial_cells;
        std::vector<Point<dim>> vertices;
        vertices.reserve((nr + 1) * nt * (nz + 1));
        for (unsigned int k = 0; k <= nz; ++k)
          for (unsigned int j = 0; j < nt; ++j)
            for (unsigned int i = 0; i <= nr; ++i)
              {
                const double r     = inner_radius + (outer_radius - inner_radius) * i / nr;
                const double theta = 2 * M_PI * j / nt;
                vertices.emplace_back(center_x + r * std::cos(theta), center_y + r * std::sin(theta),
                                      z_origin + length * k / nz);
              }
        auto v = [&](unsigned int i, unsigned int j, unsigned int k) { return (k * nt + (j % nt)) * (nr + 1) + i; };
        std::vector<CellData<dim>> cells(nr * nt * nz);
        unsigned int               c = 0;
        for (unsigned int k = 0; k < nz; ++k)
          for (unsigned int j = 0; j < nt; ++j)
            for (unsigned int i = 0; i < nr; ++i, ++c)
              {
                // deal.II's lexicographic vertex order in (r, theta, z): a
                // right-handed frame, so every cell has positive volume.
                cells[c].vertices    = {v(i, j, k),         v(i + 1, j, k),     v(i, j + 1, k),
                                        v(i + 1, j + 1, k), v(i, j, k + 1),     v(i + 1, j, k + 1),
                                        v(i, j + 1, k + 1), v(i + 1, j + 1, k + 1)};
                cells[c].material_id = 0;
              }
        tria.create_triangulation(vertices, cells, SubCellData());
      }

      bool
      lattice(Lattice &l) const override
      {
        // The tensor product cylinder is its own coarse mesh. Unrolled into a
        // box of arcs at the outer radius, no two points are closer than on
        // the cylinder: its pairs are a lower bound.
        l.cells        = {{double(radial_cells), double(circumferential_cells), double(axial_cells)}};
        l.spacing      = {{(outer_radius - inner_radius) / l.cells[0], 2 * M_PI * outer_radius / l.cells[1],
                           length / l.cells[2]}};
        l.coarse_cells = l.cells[0] * l.cells[1] * l.cells[2];
        return true;
      }

      std::string
      cells_key() const override
      {
        return "Discretization/Cylinder shell/Radial cells, Circumferential cells and Axial cells";
      }

    private:
      double       inner_radius = 0, outer_radius = 0, length = 0;
      double       center_x = 0, center_y = 0, z_origin = 0;
      unsigned int radial_cells = 0, circumferential_cells = 0, axial_cells = 0;
    };
  } // namespace

  PERIDEAL_REGISTER(SceneGeometry, CylinderShell, "Cylinder shell", "Peridigm's tensor product cylinder shell.")
} // namespace perideal
