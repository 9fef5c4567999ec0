// perideal_check stability: checks the globals CSV (and the closing summary)
// of a pd_app run for the stability tests:
//
//   perideal_check stability --csv CSV [--finite] [--energy-drift B] [--energy-gain B]
//                   [--max-ratio NUM DEN B]... [--value STEP COLUMN EXPECTED TOL]...
//                   [--last COLUMN MIN MAX]... [--balance STDOUT B]
//
// - --finite: every entry of every row is finite.
// - --energy-drift: every row's E - W is within B x E0 of E0 (E = kinetic +
//   strain energy, W the external work, E0 = E of step 0).
// - --energy-gain: every row's E - W - E0 <= B x E0: the run makes no energy
//   it was not given (the energy dissipated by broken bonds, which the
//   summary's balance adds, only lowers E).
// - --max-ratio: the largest |NUM| over all rows over |DEN| of step 0 is <= B.
// - --value: |COLUMN - EXPECTED| <= TOL in the row of step STEP.
// - --last: COLUMN of the last row lies in [MIN, MAX].
// - --balance: the "energy balance error" of pd_app's closing summary in
//   STDOUT is at most B in magnitude.
// Prints the numbers (3 digits, so that runs on 1 and 2 ranks print the
// same) with PASS/FAIL; non-zero exit on failure. Serial; no MPI.

#include "check.h"

#include <algorithm>
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
  using check_common::failures;
  using check_common::Row;
  using check_common::str;

  void
  check(const std::string &name, const double value, const bool ok, const std::string &bound)
  {
    check_common::check(name, value, ok, bound, 3);
  }

  std::vector<Row>
  read_rows(const std::string &file)
  {
    const std::vector<Row> rows = check_common::read_rows(file);
    if (rows.empty() || rows.front().at("step") != 0)
      throw std::runtime_error("no row of step 0 in " + file);
    return rows;
  }

  double
  column(const Row &row, const std::string &name)
  {
    const auto it = row.find(name);
    if (it == row.end())
      throw std::runtime_error("no column " + name);
    return it->second;
  }

  double
  energy(const Row &row)
  {
    return column(row, "kinetic_energy") + column(row, "strain_energy");
  }

  double
  summary_balance(const std::string &file)
  {
    std::ifstream in(file);
    if (!in)
      throw std::runtime_error("cannot open " + file);
    const std::regex pattern(R"(energy balance error:\s+([-0-9.eE+]+|-?nan|-?inf))");
    std::smatch      m;
    for (std::string line; std::getline(in, line);)
      if (std::regex_search(line, m, pattern))
        return std::strtod(m[1].str().c_str(), nullptr);
    throw std::runtime_error("no energy balance error in " + file);
  }
} // namespace

int
check_stability(int argc, char *argv[])
{
  try
    {
      std::string csv;
      for (int a = 1; a + 1 < argc; ++a)
        if (std::string(argv[a]) == "--csv")
          csv = argv[a + 1];
      if (csv.empty())
        throw std::runtime_error("--csv is required");
      const std::vector<Row> rows = read_rows(csv);
      const double           e0   = energy(rows.front());

      for (int a = 1; a < argc; ++a)
        {
          const std::string arg  = argv[a];
          const auto        next = [&]() { return check_common::next_argument(argc, argv, a, arg); };
          const auto number = [&]() { return std::strtod(next().c_str(), nullptr); };
          if (arg == "--csv")
            next();
          else if (arg == "--finite")
            {
              unsigned int bad = 0;
              for (const auto &row : rows)
                for (const auto &entry : row)
                  bad += !std::isfinite(entry.second);
              check("non-finite entries in " + std::to_string(rows.size()) + " rows", bad, bad == 0, "= 0");
            }
          else if (arg == "--energy-drift")
            {
              const double bound = number();
              double       worst = 0;
              for (const auto &row : rows)
                worst = std::max(worst, std::abs(energy(row) - column(row, "external_work") - e0) / e0);
              check("max |E - W - E0| / E0 (E = kinetic + strain)", worst, worst <= bound, "<= " + str(bound));
            }
          else if (arg == "--energy-gain")
            {
              const double bound = number();
              double       worst = -1e300;
              for (const auto &row : rows)
                worst = std::max(worst, (energy(row) - column(row, "external_work") - e0) / e0);
              check("max (E - W - E0) / E0", worst, worst <= bound, "<= " + str(bound));
            }
          else if (arg == "--max-ratio")
            {
              const std::string num = next(), den = next();
              const double      bound = number();
              double            worst = 0;
              for (const auto &row : rows)
                worst = std::max(worst, std::abs(column(row, num)));
              const double ratio = worst / std::abs(column(rows.front(), den));
              check("max |" + num + "| / |" + den + " of step 0|", ratio, ratio <= bound, "<= " + str(bound));
            }
          else if (arg == "--value")
            {
              const double      step = number();
              const std::string name = next();
              const double      expected = number(), tol = number();
              const auto        row = std::find_if(rows.begin(), rows.end(), [&](const Row &r) { return r.at("step") == step; });
              if (row == rows.end())
                throw std::runtime_error("no row of step " + str(step));
              const double error = std::abs(column(*row, name) - expected);
              check("|" + name + " - " + str(expected) + "| at step " + str(step), error, error <= tol, "<= " + str(tol));
            }
          else if (arg == "--last")
            {
              const std::string name = next();
              const double      lo = number(), hi = number();
              const double      value = column(rows.back(), name);
              check(name + " at the end", value, value >= lo && value <= hi, "in [" + str(lo) + ", " + str(hi) + "]");
            }
          else if (arg == "--balance")
            {
              const std::string out   = next();
              const double      bound = number();
              const double      b     = summary_balance(out);
              check("|energy balance error| of the summary", std::abs(b), std::abs(b) <= bound, "<= " + str(bound));
            }
          else
            throw std::runtime_error("unknown argument " + arg);
        }
    }
  catch (const std::exception &e)
    {
      std::cout << "Error: " << e.what() << std::endl;
      return 2;
    }
  return check_common::finish();
}
