#include <perideal/material/elastic_constants.h>

#include <cmath>
#include <map>
#include <sstream>
#include <vector>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    const char *const bulk = "Bulk modulus", *const shear = "Shear modulus", *const young = "Young's modulus",
                      *const poisson = "Poisson's ratio";

    /// 6 significant digits, as the messages quote them.
    std::string
    number(const double v)
    {
      std::ostringstream out;
      out << v;
      return out.str();
    }

    /// The keys given (non-empty), in the order K, G, E, nu, with their
    /// values, each checked on its own.
    std::vector<std::pair<std::string, double>>
    given_keys(ParameterHandler &prm, const std::string &path)
    {
      std::vector<std::pair<std::string, double>> given;
      for (const char *key : {bulk, shear, young, poisson})
        {
          const std::string text = prm.get(key);
          if (text.find_first_not_of(" \t") == std::string::npos)
            continue;
          double      value = 0;
          std::size_t end   = 0;
          try
            {
              value = std::stod(text, &end);
            }
          catch (const std::exception &)
            {
              end = 0;
            }
          AssertThrow(end > 0 && text.find_first_not_of(" \t", end) == std::string::npos && std::isfinite(value),
                      ExcMessage(path + "/" + key + ": '" + text + "' is not a finite number"));
          if (key == poisson)
            {
              AssertThrow(value > -1 && value < 0.5,
                          ExcMessage(path + "/" + key + " must be in (-1, 0.5), got " + number(value)));
            }
          else
            require_positive(value, path + "/" + key);
          given.emplace_back(key, value);
        }
      return given;
    }

    std::string
    names(const std::vector<std::pair<std::string, double>> &given, const std::string &path)
    {
      std::string list;
      for (const auto &[key, value] : given)
        list += (list.empty() ? "" : ", ") + path + "/" + key + " = " + number(value);
      return list.empty() ? "none" : list;
    }

    /// K and G from a pair of valid single values; checks what the pair implies.
    ElasticConstants
    from_pair(const std::vector<std::pair<std::string, double>> &given, const std::string &path)
    {
      std::map<std::string, double> v(given.begin(), given.end());
      const auto has = [&](const char *a, const char *b) { return v.count(a) && v.count(b); };
      ElasticConstants c;
      if (has(bulk, shear))
        c = {v[bulk], v[shear]};
      else if (has(young, poisson))
        c = {v[young] / (3 * (1 - 2 * v[poisson])), v[young] / (2 * (1 + v[poisson]))};
      else if (has(bulk, young))
        c = {v[bulk], 3 * v[bulk] * v[young] / (9 * v[bulk] - v[young])};
      else if (has(bulk, poisson))
        c = {v[bulk], 3 * v[bulk] * (1 - 2 * v[poisson]) / (2 * (1 + v[poisson]))};
      else if (has(shear, young))
        c = {v[young] * v[shear] / (3 * (3 * v[shear] - v[young])), v[shear]};
      else
        c = {2 * v[shear] * (1 + v[poisson]) / (3 * (1 - 2 * v[poisson])), v[shear]};
      // Only (K, E) and (G, E) can imply a bad pair: E >= 9K, or E <= 2G
      // or E >= 3G, i.e. nu outside (-1, 0.5).
      const double nu = v.count(bulk) && v.count(young) ? (3 * v[bulk] - v[young]) / (6 * v[bulk]) :
                        v.count(shear) && v.count(young) ? v[young] / (2 * v[shear]) - 1 :
                                                            c.poissons_ratio();
      AssertThrow(nu > -1 && nu < 0.5 && c.K > 0 && c.G > 0 && std::isfinite(c.K) && std::isfinite(c.G),
                  ExcMessage(names(given, path) + " imply Poisson's ratio " + number(nu) +
                             ", outside (-1, 0.5) (bulk modulus " + number(c.K) + ", shear modulus " +
                             number(c.G) + "): an isotropic solid needs K > 0 and G > 0"));
      return c;
    }
  } // namespace

  void
  declare_elastic_constants(ParameterHandler &prm)
  {
    const std::string any = " Give two of Bulk modulus, Shear modulus, Young's modulus, Poisson's ratio (a "
                            "bond-based model: one modulus, its Poisson's ratio being 1/4); empty: not given.";
    prm.declare_entry(bulk, "", Patterns::Anything(), "Bulk modulus K." + any);
    prm.declare_entry(shear, "", Patterns::Anything(), "Shear modulus G." + any);
    prm.declare_entry(young, "", Patterns::Anything(), "Young's modulus E = 9KG/(3K + G)." + any);
    prm.declare_entry(poisson, "", Patterns::Anything(),
                      "Poisson's ratio nu = (3K - 2G)/(2(3K + G)), in (-1, 0.5)." + any);
  }

  ElasticConstants
  parse_elastic_constants(ParameterHandler &prm, const std::string &path)
  {
    const auto given = given_keys(prm, path);
    AssertThrow(given.size() == 2,
                ExcMessage(path + ": give exactly two of Bulk modulus, Shear modulus, Young's modulus, "
                                  "Poisson's ratio (any pair); given: " +
                           names(given, path)));
    return from_pair(given, path);
  }

  ElasticConstants
  parse_bond_based_elastic_constants(ParameterHandler &prm, const std::string &path)
  {
    const auto given = given_keys(prm, path);
    const std::string rule = "a bond-based model has Poisson's ratio 1/4 by construction (G = 3K/5): give one "
                             "modulus (Bulk modulus, Young's modulus or Shear modulus), or use a state-based "
                             "model (LPS) for another Poisson's ratio";
    AssertThrow(!given.empty() && given.size() <= 2 && !(given.size() == 1 && given[0].first == poisson),
                ExcMessage(path + ": " + rule + "; given: " + names(given, path)));
    if (given.size() == 1)
      {
        const double v = given[0].second;
        const std::string &key = given[0].first;
        // nu = 1/4: E = 9KG/(3K + G) = 3K/2, G = 3K/5.
        const double K = key == bulk ? v : key == young ? 2 * v / 3 : 5 * v / 3;
        return {K, 0.6 * K};
      }
    const ElasticConstants c  = from_pair(given, path);
    const double           nu = c.poissons_ratio();
    AssertThrow(std::abs(nu - 0.25) < 1e-12,
                ExcMessage(path + ": " + names(given, path) + " imply Poisson's ratio " + number(nu) + ", but " +
                           rule));
    return {c.K, 0.6 * c.K};
  }

  void
  declare_thermal_expansion(ParameterHandler &prm)
  {
    prm.declare_entry("Thermal expansion coefficient", "0", Patterns::Double(),
                      "alpha: a free bond (a free body) strains by alpha (T - T_ref)");
  }

  double
  parse_thermal_expansion(ParameterHandler &prm, const std::string &path)
  {
    const double alpha = prm.get_double("Thermal expansion coefficient");
    AssertThrow(std::isfinite(alpha), ExcMessage(path + "/Thermal expansion coefficient must be finite, not " +
                                                 prm.get("Thermal expansion coefficient")));
    return alpha;
  }
} // namespace perideal
