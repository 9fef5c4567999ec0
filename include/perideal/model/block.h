#pragma once
// A block: a set of cells with one material (and optional damage model) and
// one horizon, a continuum (FE) block, or a rigid block (model/rigid_bodies.h). Blocks/NAME of the parameter file.

#include <perideal/continuum/continuum_model.h>
#include <perideal/damage/damage_model.h>
#include <perideal/material/material.h>

#include <memory>
#include <string>
#include <vector>

namespace perideal
{
  struct Block
  {
    std::string               name;
    std::vector<unsigned int> material_ids;
    std::string               region;
    std::string               material_name, damage_name;
    double                    horizon   = 0;
    double                    neglect_damage = 1; // its damage model's Critical damage to neglect material point (1: never)
    bool                      continuum = false; // FE cells; its points are virtual points
    bool                      rigid     = false; // moves as one body; no bonds; its material gives only the density
    unsigned int              fe_degree = 1;
    std::unique_ptr<ContinuumModel>   continuum_model; // continuum blocks only
    std::unique_ptr<Material>         material;
    std::unique_ptr<DamageModel>      damage;
    std::vector<unsigned int>         points; // owned points of this block (virtual points for continuum blocks)
  };
} // namespace perideal
