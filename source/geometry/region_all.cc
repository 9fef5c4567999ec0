// Region Type = All: every point.
#include <perideal/geometry/region.h>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class AllRegion : public RegionSelector
    {
    public:
      static void
      declare_parameters(ParameterHandler &)
      {}

      void
      parse_parameters(ParameterHandler &, const std::string &, const SceneGeometry &) override
      {}

      bool
      contains(const Point<dim> &, const DoFHandler<dim>::active_cell_iterator &) const override
      {
        return true;
      }
    };
  } // namespace

  PERIDEAL_REGISTER(RegionSelector, AllRegion, "All", "every point.")
} // namespace perideal
