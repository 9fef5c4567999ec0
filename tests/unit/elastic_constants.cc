// Elastic constants (include/perideal/material/elastic_constants.h): every
// pair of K, G, E, nu gives the same K and G (to 1e-14 relative), bad pairs
// and counts throw naming the keys, and the bond-based parse takes one
// modulus or a pair with nu = 1/4 only.
#include <perideal/material/elastic_constants.h>

#include <cmath>
#include <iostream>
#include <map>
#include <sstream>
#include <algorithm>
#include <iomanip>
#include <iterator>

using namespace perideal;

namespace
{
  int failures = 0;

  std::string
  exact(const double v)
  {
    std::ostringstream o;
    o << std::setprecision(17) << v;
    return o.str();
  }

  ParameterHandler &
  deck(ParameterHandler &prm, const std::map<std::string, std::string> &keys)
  {
    declare_elastic_constants(prm);
    for (const auto &[key, value] : keys)
      prm.set(key, value);
    return prm;
  }

  void
  expect(const bool ok, const std::string &what)
  {
    std::cout << (ok ? "PASS " : "FAIL ") << what << '\n';
    failures += !ok;
  }

  /// The message of the exception @p parse throws, or "" if it returns.
  template <typename F>
  std::string
  error_of(const F &parse)
  {
    try
      {
        parse();
      }
    catch (const dealii::ExceptionBase &e)
      {
        std::ostringstream m;
        e.print_info(m);
        return m.str();
      }
    return "";
  }
} // namespace

int
main()
{
  // nu = 0.31: K = 2.5, G = 1.1.
  const double K = 2.5, G = 1.1, E = 9 * K * G / (3 * K + G), nu = (3 * K - 2 * G) / (2 * (3 * K + G));
  const std::map<std::string, double> value = {
    {"Bulk modulus", K}, {"Shear modulus", G}, {"Young's modulus", E}, {"Poisson's ratio", nu}};
  for (auto a = value.begin(); a != value.end(); ++a)
    for (auto b = std::next(a); b != value.end(); ++b)
      {
        ParameterHandler prm;
        const ElasticConstants c =
          parse_elastic_constants(deck(prm, {{a->first, exact(a->second)}, {b->first, exact(b->second)}}), "m");
        const double error = std::max({std::abs(c.K / K - 1), std::abs(c.G / G - 1),
                                       std::abs(c.youngs_modulus() / E - 1), std::abs(c.poissons_ratio() / nu - 1)});
        expect(error < 1e-14, a->first + ", " + b->first + ": K, G, E, nu within 1e-14 (" + exact(error) + ")");
      }
  {
    ElasticConstants c{K, G};
    expect(std::abs(c.lame_lambda() - (K - 2 * G / 3)) < 1e-15 &&
             std::abs(c.lame_lambda() - E * nu / ((1 + nu) * (1 - 2 * nu))) < 1e-14,
           "lambda = K - 2G/3 = E nu / ((1 + nu)(1 - 2 nu))");
  }
  // Poisson's ratio 0 is a value, not "not given".
  {
    ParameterHandler prm;
    const ElasticConstants c = parse_elastic_constants(deck(prm, {{"Young's modulus", "3"}, {"Poisson's ratio", "0"}}), "m");
    expect(std::abs(c.K - 1) < 1e-15 && std::abs(c.G - 1.5) < 1e-15, "E = 3, nu = 0: K = 1, G = 1.5");
  }
  const auto fails_with = [](const std::map<std::string, std::string> &keys, const std::string &text, const bool bond_based) {
    ParameterHandler  prm;
    const std::string m = error_of([&] {
      deck(prm, keys);
      bond_based ? parse_bond_based_elastic_constants(prm, "m") : parse_elastic_constants(prm, "m");
    });
    expect(m.find(text) != std::string::npos, "error '" + text + "' (got: " + m + ")");
  };
  fails_with({{"Bulk modulus", "1"}}, "m: give exactly two of", false);
  fails_with({{"Bulk modulus", "1"}, {"Shear modulus", "1"}, {"Poisson's ratio", "0.2"}},
             "given: m/Bulk modulus = 1, m/Shear modulus = 1, m/Poisson's ratio = 0.2", false);
  fails_with({{"Bulk modulus", "1"}, {"Poisson's ratio", "0.5"}}, "m/Poisson's ratio must be in (-1, 0.5), got 0.5", false);
  fails_with({{"Bulk modulus", "1"}, {"Young's modulus", "10"}},
             "m/Bulk modulus = 1, m/Young's modulus = 10 imply Poisson's ratio -1.16667, outside (-1, 0.5)", false);
  fails_with({{"Shear modulus", "1"}, {"Young's modulus", "3"}}, "imply Poisson's ratio 0.5, outside", false);
  fails_with({{"Shear modulus", "0"}, {"Young's modulus", "3"}}, "m/Shear modulus must be positive, got 0", false);
  fails_with({{"Bulk modulus", "1e"}, {"Young's modulus", "3"}}, "m/Bulk modulus: '1e' is not a finite number", false);
  // Bond based: one modulus, or nu = 1/4.
  for (const auto &[key, v] : std::map<std::string, double>{{"Bulk modulus", 3}, {"Young's modulus", 4.5}, {"Shear modulus", 1.8}})
    {
      ParameterHandler       prm;
      const ElasticConstants c = parse_bond_based_elastic_constants(deck(prm, {{key, exact(v)}}), "m");
      expect(std::abs(c.K - 3) < 1e-15 && std::abs(c.G - 1.8) < 1e-15, "bond based, " + key + " alone: K = 3, G = 1.8");
    }
  {
    ParameterHandler       prm;
    const ElasticConstants c =
      parse_bond_based_elastic_constants(deck(prm, {{"Young's modulus", "4.5"}, {"Poisson's ratio", "0.25"}}), "m");
    expect(std::abs(c.K - 3) < 1e-14, "bond based, E = 4.5 and nu = 1/4: K = 3");
  }
  fails_with({{"Young's modulus", "4.5"}, {"Poisson's ratio", "0.3"}},
             "imply Poisson's ratio 0.3, but a bond-based model has Poisson's ratio 1/4 by construction", true);
  fails_with({{"Poisson's ratio", "0.25"}}, "give one modulus", true);
  fails_with({}, "given: none", true);
  std::cout << (failures ? "FAILED\n" : "ALL PASSED\n");
  return failures ? 1 : 0;
}
