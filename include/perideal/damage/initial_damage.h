#pragma once
// Initial damage (Discretization/Initial damage): bonds that start broken.
// Unlike a bond filter, which leaves a bond out of the families, an initially
// broken bond stays in its family: it counts in the point damage
// (1 - intact volume / family volume) and in what a state-based material
// weights by its reference family (LPS's weighted volume m), exactly as a
// bond broken in the run does, and a damage model never mends it. Two
// shapes:
//   Rectangular plane: bonds whose reference segment meets the rectangle
//     (BondFilter's geometry: Peridigm's Rectangular_Plane);
//   Region: bonds with at least one end point in the region, so the region
//     starts cut out of the body along its boundary.
// Both owners of a bond decide from the same data, so i->j and j->i agree.

#include <perideal/base/input.h>
#include <perideal/neighborhood/bond_filter.h>

#include <string>

namespace perideal
{
  class InitialDamage
  {
  public:
    enum class Type
    {
      plane,
      region
    };

    static void
    declare_parameters(ParameterHandler &prm);
    /// @p path names the subsection in error messages.
    void
    parse_parameters(ParameterHandler &prm, const std::string &path);

    std::string name;
    Type        type = Type::plane;
    BondFilter  plane;  // Type::plane
    std::string region; // Type::region: a name of Discretization/Regions
  };
} // namespace perideal
