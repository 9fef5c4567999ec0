// A region's Type, chosen from Registry<RegionSelector>, and its selector.
#include <perideal/geometry/region.h>

namespace perideal
{
  using namespace dealii;

  void
  Region::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Type", "Box", Registry<RegionSelector>::instance().selection(),
                      "How the region is chosen. " + Registry<RegionSelector>::instance().documentation());
    for (const auto &[name, entry] : Registry<RegionSelector>::instance().all())
      entry.declare(prm);
  }

  void
  Region::parse_parameters(ParameterHandler &prm, const std::string &path, const SceneGeometry &geometry)
  {
    selector = Registry<RegionSelector>::instance().create(prm.get("Type"), path + "/Type");
    selector->parse_parameters(prm, path, geometry);
  }
} // namespace perideal
