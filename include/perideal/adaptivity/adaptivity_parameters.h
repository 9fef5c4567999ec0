#pragma once
// The Adaptivity section of the parameter file (doc/adaptivity.md); the
// conversion itself is adaptivity.h.

#include <perideal/base/input.h>

#include <string>
#include <vector>

namespace perideal
{
  struct Block;

  /// The Adaptivity section of the parameter file.
  struct AdaptivityParameters
  {
    enum class Indicator
    {
      principal_strain, // largest principal strain / s_c of the PD block's damage model
      energy_density,   // strain energy density / (E s_c^2 / 2)
      damage            // largest damage of a PD point within the buffer
    };

    static void
    declare_parameters(ParameterHandler &prm);
    /// Reads the section; the block names are checked by resolve().
    void
    parse_parameters(ParameterHandler &prm);
    /// Checks the blocks against @p blocks (convertible ones continuum
    /// blocks of the Peridynamic block's material, which is peridynamic
    /// with a damage model where the indicator needs its critical stretch)
    /// and sets the block numbers. An Error names the key.
    void
    resolve(const std::vector<Block> &blocks);
    bool
    active() const
    {
      return !convertible_names.empty();
    }

    std::vector<std::string>  convertible_names;
    std::string               pd_block_name;
    Indicator                 indicator      = Indicator::principal_strain;
    double                    threshold      = 0.5;
    unsigned int              check_interval = 0; // 0: 10 explicit steps, every implicit step
    double                    buffer         = 0; // 0: the rule (doc/adaptivity.md)
    double                    margin         = 0; // converts with the buffer
    bool                      check_kept     = false; // search the kept families again (tests)
    bool                      refine         = false; // refine converted cells to the PD block's finest level
    double                    rebalance      = 0.25;  // repartition when the work is out of balance by more (0: never)
    std::vector<unsigned int> convertible;        // block numbers
    unsigned int              pd_block = 0;
  };

} // namespace perideal
