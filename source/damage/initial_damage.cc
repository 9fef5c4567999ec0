#include <perideal/damage/initial_damage.h>

#include <deal.II/base/utilities.h>

namespace perideal
{
  using namespace dealii;

  void
  InitialDamage::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Type", "Rectangular plane", Patterns::Selection("Rectangular plane|Region"),
                      "Rectangular plane: the bonds that cross the rectangle start broken (its keys as a bond "
                      "filter's). Region: the bonds with an end point in Region start broken.");
    prm.declare_entry("Region", "", Patterns::Anything(),
                      "Type = Region: a name of Discretization/Regions (not All).");
    BondFilter::declare_plane_parameters(prm);
  }

  void
  InitialDamage::parse_parameters(ParameterHandler &prm, const std::string &path)
  {
    type = prm.get("Type") == "Region" ? Type::region : Type::plane;
    if (type == Type::plane)
      {
        plane.parse_parameters(prm, path);
        plane.name = name;
      }
    else
      {
        region = Utilities::trim(prm.get("Region"));
        AssertThrow(!region.empty(), ExcMessage(path + "/Region: Type is Region, so name a region of "
                                                       "Discretization/Regions"));
        AssertThrow(region != "All", ExcMessage(path + "/Region: 'All' would break every bond; name a "
                                                       "region of Discretization/Regions"));
      }
  }
} // namespace perideal
