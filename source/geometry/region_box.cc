// Region Type = Box: the points in an axis-aligned box, bounds included.
#include <perideal/geometry/region.h>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class BoxRegion : public RegionSelector
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Lower corner", "0,0,0", Patterns::List(Patterns::Double(), 3, 3), "Box: x,y,z of the lower corner.");
        prm.declare_entry("Upper corner", "0,0,0", Patterns::List(Patterns::Double(), 3, 3), "Box: x,y,z of the upper corner.");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path, const SceneGeometry &) override
      {
        lower = get_point(prm, "Lower corner");
        upper = get_point(prm, "Upper corner");
        for (unsigned int d = 0; d < dim; ++d)
          AssertThrow(upper[d] >= lower[d],
                      ExcMessage(path + ": the upper corner must not be below the "
                                        "lower corner"));
      }

      bool
      contains(const Point<dim> &x, const DoFHandler<dim>::active_cell_iterator &) const override
      {
        for (unsigned int d = 0; d < dim; ++d)
          if (x[d] < lower[d] || x[d] > upper[d])
            return false;
        return true;
      }

    private:
      Point<dim> lower, upper;
    };
  } // namespace

  PERIDEAL_REGISTER(RegionSelector, BoxRegion, "Box",
                    "a point (cell centroid) is in a Box if every coordinate lies in [lower, upper] (bounds "
                    "included).")
} // namespace perideal
