#pragma once
// Isotropic elastic constants from any two of the bulk modulus K, the shear
// modulus G, Young's modulus E and Poisson's ratio nu: the keys "Bulk
// modulus", "Shear modulus", "Young's modulus", "Poisson's ratio" of a
// material subsection. An empty value means "not given" (so that "Poisson's
// ratio = 0" is a value like any other).

#include <perideal/base/input.h>

#include <string>

namespace perideal
{
  /// K and G, and what follows from them.
  struct ElasticConstants
  {
    double K = 0, G = 0;

    double
    youngs_modulus() const
    {
      return 9 * K * G / (3 * K + G);
    }
    double
    poissons_ratio() const
    {
      return (3 * K - 2 * G) / (2 * (3 * K + G));
    }
    /// Lame's first parameter lambda = K - 2G/3.
    double
    lame_lambda() const
    {
      return K - 2 * G / 3;
    }
  };

  /// Declares the four keys (empty defaults) in the current subsection.
  void
  declare_elastic_constants(ParameterHandler &prm);

  /// Exactly two of the four keys: K and G from them. Anything else (fewer,
  /// more, a value out of range, or a pair implying K <= 0, G <= 0 or nu
  /// outside (-1, 0.5)) throws ExcMessage naming the keys under @p path.
  ElasticConstants
  parse_elastic_constants(ParameterHandler &prm, const std::string &path);

  /// A bond-based model, whose Poisson's ratio is 1/4 (G = 3K/5) by
  /// construction: one modulus (K, E or G) alone, or two keys that imply
  /// nu = 1/4; another Poisson's ratio throws, saying why.
  ElasticConstants
  parse_bond_based_elastic_constants(ParameterHandler &prm, const std::string &path);

  /// Declares "Thermal expansion coefficient" (default 0: no thermal strain),
  /// the key every material has (ModelState::thermal_strain).
  void
  declare_thermal_expansion(ParameterHandler &prm);

  /// Its value; a non-finite one throws naming the key under @p path.
  double
  parse_thermal_expansion(ParameterHandler &prm, const std::string &path);
} // namespace perideal
