// Discretization/Type = Box: a box of hexahedra, Subdivisions cells along
// each axis.
#include <perideal/geometry/scene.h>

#include <deal.II/base/utilities.h>
#include <deal.II/grid/grid_generator.h>

#include <algorithm>
#include <cmath>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class BoxScene : public SceneGeometry
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Box");
        prm.declare_entry("Lower corner", "0,0,0", Patterns::List(Patterns::Double(), 3, 3), "x,y,z of the lower corner.");
        prm.declare_entry("Upper corner", "1,1,1", Patterns::List(Patterns::Double(), 3, 3), "x,y,z of the upper corner.");
        prm.declare_entry("Subdivisions", "10,10,10", Patterns::List(Patterns::Integer(1), 3, 3), "Cells along x, y and z.");
        prm.leave_subsection();
      }

      void
      parse_parameters(ParameterHandler &prm, const double horizon) override
      {
        prm.enter_subsection("Box");
        lower = get_point(prm, "Lower corner");
        upper = get_point(prm, "Upper corner");
        const auto v = Utilities::string_to_int(Utilities::split_string_list(prm.get("Subdivisions"), ','));
        for (unsigned int d = 0; d < dim; ++d)
          subdivisions[d] = v[d];
        prm.leave_subsection();

        // Finite corners, and a box whose coordinates, spacing and horizon fit
        // in double (else the mesh or the neighbor search would be blamed for
        // an overflow).
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
            AssertThrow(resolvable(std::max(std::abs(lower[d]), std::abs(upper[d])), spacing, horizon),
                        ExcMessage(std::string("Discretization/Box: the cell size along ") + axis[d] + " (" +
                                   Utilities::to_string(spacing) +
                                   ") is too small for the coordinates (Lower corner " +
                                   Utilities::to_string(lower[d]) + ", Upper corner " +
                                   Utilities::to_string(upper[d]) +
                                   "): points would not be told apart in double; move the box "
                                   "near the origin or use fewer Subdivisions"));
          }
      }

      void
      create_triangulation(parallel::distributed::Triangulation<dim> &tria) const override
      {
        // p4est keeps the coarse mesh on every rank: use the coarsest mesh that
        // refines to the requested subdivisions.
        const unsigned int        k = refinements();
        std::vector<unsigned int> coarse(dim);
        for (unsigned int d = 0; d < dim; ++d)
          coarse[d] = subdivisions[d] >> k;
        GridGenerator::subdivided_hyper_rectangle(tria, coarse, lower, upper);
        tria.refine_global(k);
      }

      bool
      lattice(Lattice &l) const override
      {
        // As create_triangulation: a coarse mesh of Subdivisions / 2^k cells refined k times.
        const unsigned int k = refinements();
        l.coarse_cells       = 1;
        for (unsigned int d = 0; d < dim; ++d)
          {
            l.cells[d]   = subdivisions[d];
            l.spacing[d] = (upper[d] - lower[d]) / l.cells[d];
            l.coarse_cells *= double(subdivisions[d] >> k);
          }
        return true;
      }

      long
      n_numbered_points() const override
      {
        return long(subdivisions[0]) * subdivisions[1] * subdivisions[2];
      }

      long
      point_number(const Point<dim> &x) const override
      {
        long number = 0;
        for (int d = dim - 1; d >= 0; --d)
          {
            const double h = (upper[d] - lower[d]) / subdivisions[d];
            const long   i = std::clamp(long(std::floor((x[d] - lower[d]) / h)), 0L, long(subdivisions[d]) - 1);
            number         = number * subdivisions[d] + i;
          }
        return number + 1;
      }

      std::string
      cells_key() const override
      {
        return "Discretization/Box/Subdivisions";
      }

    private:
      /// The global refinements of the coarsest mesh: the common factors 2 of
      /// the subdivisions, at most 6.
      unsigned int
      refinements() const
      {
        unsigned int k = 6;
        for (unsigned int d = 0; d < dim; ++d)
          {
            unsigned int z = 0, s = subdivisions[d];
            while (s % 2 == 0 && s > 1)
              s /= 2, ++z;
            k = std::min(k, z);
          }
        return k;
      }

      Point<dim>                  lower, upper;
      std::array<unsigned int, 3> subdivisions{};
    };
  } // namespace

  PERIDEAL_REGISTER(SceneGeometry, BoxScene, "Box", "a box of hexahedra.")
} // namespace perideal
