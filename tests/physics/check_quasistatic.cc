// Checks a quasistatic pd_app run: region computes of its globals CSV against
// expected values, and the convergence of Newton from its stdout.
//
//   check_quasistatic CSV STDOUT STEP SCALE TOL MIN_ORDER MAX_ITERATIONS [NAME=VALUE ...]
//
// - every column NAME of the CSV row of load step STEP: |value - VALUE| <= TOL x SCALE;
// - every load step converges in at most MAX_ITERATIONS Newton iterations;
// - quadratic convergence: for every Newton iteration k >= 2 whose residual
//   r_k is above the round-off floor (1e-13 x r_0 of its solve), the order
//   log(r_k / r_{k-1}) / log(r_{k-1} / r_{k-2}) >= MIN_ORDER; at least one
//   such iteration must exist.
// Prints the numbers with PASS/FAIL; non-zero exit on failure. Serial; no MPI.

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
  unsigned int failures = 0;

  std::string
  str(const double v)
  {
    std::ostringstream o;
    o << std::setprecision(3) << v;
    return o.str();
  }

  void
  check(const std::string &name, const double value, const bool ok, const std::string &bound)
  {
    std::cout << std::setprecision(6) << name << " = " << value << "  (" << bound << ")  " << (ok ? "PASS" : "FAIL")
              << "\n";
    if (!ok)
      ++failures;
  }

  std::map<std::string, double>
  read_row(const std::string &file, const double step)
  {
    std::ifstream in(file);
    if (!in)
      throw std::runtime_error("cannot open " + file);
    std::string              line;
    std::vector<std::string> header;
    std::getline(in, line);
    std::stringstream h(line);
    for (std::string c; std::getline(h, c, ',');)
      header.push_back(c);
    while (std::getline(in, line))
      {
        std::stringstream             s(line);
        std::map<std::string, double> row;
        std::string                   c;
        for (unsigned int k = 0; k < header.size() && std::getline(s, c, ','); ++k)
          row[header[k]] = std::atof(c.c_str());
        if (row.count("step") && row["step"] == step)
          return row;
      }
    throw std::runtime_error("no row of step " + std::to_string(step) + " in " + file);
  }
} // namespace

int
main(int argc, char *argv[])
{
  try
    {
      if (argc < 8)
        throw std::runtime_error("usage: check_quasistatic CSV STDOUT STEP SCALE TOL MIN_ORDER MAX_ITERATIONS [NAME=VALUE ...]");
      const double       step      = std::atof(argv[3]);
      const double       scale     = std::atof(argv[4]);
      const double       tol       = std::atof(argv[5]);
      const double       min_order = std::atof(argv[6]);
      const unsigned int max_it    = std::atoi(argv[7]);

      const auto row = read_row(argv[1], step);
      for (int a = 8; a < argc; ++a)
        {
          const std::string arg = argv[a];
          const auto        eq  = arg.find('=');
          const std::string name = arg.substr(0, eq);
          const double      expected = std::atof(arg.substr(eq + 1).c_str());
          if (!row.count(name))
            throw std::runtime_error("no column " + name);
          std::cout << std::setprecision(10) << name << " = " << row.at(name) << " (expected " << expected << ")\n";
          const double error = std::abs(row.at(name) - expected) / scale;
          check("  |" + name + " - expected| / scale", error, error <= tol, "<= " + str(tol));
        }

      // Newton histories: "Load step k/N" starts a step, "Newton i: |R| = r" an iteration.
      std::ifstream in(argv[2]);
      if (!in)
        throw std::runtime_error(std::string("cannot open ") + argv[2]);
      const std::regex                 newton(R"(^\s*Newton (\d+): \|R\| = ([0-9.eE+-]+))");
      std::vector<std::vector<double>> solves;
      std::string                      line;
      std::smatch                      m;
      while (std::getline(in, line))
        if (std::regex_search(line, m, newton))
          {
            if (std::stoi(m[1]) == 0)
              solves.emplace_back();
            if (solves.empty())
              throw std::runtime_error("a Newton line before iteration 0");
            solves.back().push_back(std::atof(m[2].str().c_str()));
          }
      if (solves.empty())
        throw std::runtime_error("no Newton iterations in " + std::string(argv[2]));
      unsigned int most = 0, orders = 0;
      double       worst = 1e300;
      for (unsigned int s = 0; s < solves.size(); ++s)
        {
          const auto &r = solves[s];
          most          = std::max<unsigned int>(most, r.size() - 1);
          std::cout << "solve " << s + 1 << ": " << r.size() - 1 << " iterations, |R_k|/|R_0|:";
          for (unsigned int k = 1; k < r.size(); ++k)
            std::cout << " " << std::setprecision(2) << (r[k] > 1e-13 * r[0] ? r[k] / r[0] : 0.0);
          std::cout << "\n";
          for (unsigned int k = 2; k < r.size(); ++k)
            if (r[k] > 1e-13 * r[0])
              {
                const double order = std::log(r[k] / r[k - 1]) / std::log(r[k - 1] / r[k - 2]);
                std::cout << "  order at iteration " << k << ": " << std::setprecision(3) << order << "\n";
                worst = std::min(worst, order);
                ++orders;
              }
        }
      check("most Newton iterations in a solve", most, most <= max_it, "<= " + std::to_string(max_it));
      check("iterations above round-off with an order estimate", orders, orders > 0, "> 0");
      check("smallest convergence order", orders ? worst : 0, orders > 0 && worst >= min_order,
            ">= " + str(min_order));
    }
  catch (const std::exception &e)
    {
      std::cout << "Error: " << e.what() << std::endl;
      return 2;
    }
  std::cout << (failures == 0 ? "ALL PASSED" : std::to_string(failures) + " CHECK(S) FAILED") << std::endl;
  return failures == 0 ? 0 : 1;
}
