// perideal_check quasistatic: checks a pd_app run (implicit: QuasiStatic or
// Newmark, or a wave) from its globals CSV and its stdout:
//
//   perideal_check quasistatic --csv CSV [--step S --scale X --tol T NAME=VALUE ...]
//                     [--stdout OUT --min-order P --max-iterations N]
//                     [--energy-drift B]
//                     [--reference CSV2 --column C --arrival-tol A --signal-tol G]
//                     [--fracture SC STRETCH REACTION]
//                     [--modulus UL UR XL XR REACTION AREA E TOL]
//                     [--energy-fraction NAME MIN MAX]...
//                     [--dissipation PEAK BALANCE]
//
// - NAME=VALUE: the column NAME of the CSV row of step S: |value - VALUE| <= T X;
//   NAME may be a sum of columns, A+B (e.g. the reactions of two supports);
// - --stdout: every solve converges in at most N Newton iterations, and for
//   every Newton iteration k >= 2 whose residual r_k is above the round-off
//   floor (1e-13 x r_0 of its solve) the order
//   log(r_k / r_{k-1}) / log(r_{k-1} / r_{k-2}) >= P (quadratic: 2); at least
//   one such iteration must exist if P > 0;
// - --energy-drift: every row's kinetic + strain energy - external work
//   (- the conversion jumps so far, column conversion_energy, where the run
//   has one: Adaptivity) is within B x its value at step 0.
// - --reference: column C against the same column of another run (times
//   interpolated linearly in CSV2): the arrival time, when C first reaches
//   half of the reference's last value, within A (relative), and
//   max |C - C_ref| <= G max |C_ref|.
// - --fracture (quasistatic with a critical stretch SC; columns STRETCH: the
//   largest bond stretch, REACTION: a support's reaction): let k be the first
//   step with a broken bond. Then the stretch of step k-1 is below SC and,
//   extrapolated in proportion to the load (time), at or above SC at step k;
//   step k was solved more than once; and at the end the reaction is below
//   5% of its largest value (the bar has come apart).
// - --modulus (a tensile test with a virtual strain gauge): in the row of step
//   S, the gauge strain (UR - UL) / (XR - XL) (columns: the mean displacement
//   and the mean position of the gauge's two ends), the stress REACTION / AREA
//   and Young's modulus stress / strain, within TOL (relative) of E.
// - --energy-fraction (an explicit wave: NAME is the kinetic energy of a
//   region at step S): twice it, the energy of a travelling wave there (kinetic
//   = strain), over the initial kinetic + strain energy, in [MIN, MAX]; may
//   be given for several columns.
// - --dissipation (a quasistatic run with a plastic or viscous material, the
//   column material_dissipation D; PEAK: the last loading step, after which
//   the load is taken back elastically): D at step PEAK > 0; D never
//   decreases from a row to the next (by more than 1e-12 of D at PEAK); after
//   PEAK it stays at its value there to 1e-12 (relative: elastic unloading
//   dissipates nothing); and in every row the energy balance external work =
//   strain + kinetic energy + D holds to BALANCE x the largest |external work|.
// Prints the numbers with PASS/FAIL; non-zero exit on failure. Serial; no MPI.

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
  using check_common::read_rows;
  using check_common::str;

  void
  check(const std::string &name, const double value, const bool ok, const std::string &bound)
  {
    std::cout << std::setprecision(6); // later lines print with it, as they always did
    check_common::check(name, value, ok, bound, 6);
  }

  std::map<std::string, double>
  read_row(const std::string &file, const double step)
  {
    for (const auto &row : read_rows(file))
      if (row.count("step") && row.at("step") == step)
        return row;
    throw std::runtime_error("no row of step " + std::to_string(step) + " in " + file);
  }
  void
  check_fracture(const std::string &csv, const double sc, const std::string &stretch, const std::string &reaction)
  {
    const auto   rows = read_rows(csv);
    unsigned int k    = 0;
    while (k < rows.size() && rows[k].at("broken_bonds") == 0)
      ++k;
    if (k == rows.size() || k < 2)
      throw std::runtime_error(k == rows.size() ? "no bond broke" : "bonds broke in the first load step");
    const auto  &before = rows[k - 1], &at = rows[k];
    const double s      = before.at(stretch);
    const double extrapolated = s * at.at("time") / before.at("time");
    std::cout << std::setprecision(6) << "first broken bonds in step " << at.at("step") << " (t = " << at.at("time")
              << "): " << at.at("broken_bonds") << "\n";
    check("largest stretch of the step before", s, s < sc, "< s_c = " + str(sc));
    check("  extrapolated to the breaking step", extrapolated, extrapolated >= sc, ">= s_c");
    check("solves of the breaking step", at.at("damage_solves"), at.at("damage_solves") >= 2, ">= 2");
    double peak = 0;
    for (const auto &row : rows)
      peak = std::max(peak, std::abs(row.at(reaction)));
    const double last = std::abs(rows.back().at(reaction));
    check("|reaction| at the end / its largest value", last / peak, last <= 0.05 * peak, "<= 0.05");
  }

  // Column C of a run against the same column of a reference run.
  void
  compare_signals(const std::string &csv, const std::string &reference, const std::string &column,
                  const double arrival_tol, const double signal_tol)
  {
    const auto series = [&](const std::string &file) {
      std::vector<std::pair<double, double>> s;
      for (const auto &row : read_rows(file))
        {
          if (!row.count(column))
            throw std::runtime_error("no column " + column + " in " + file);
          s.emplace_back(row.at("time"), row.at(column));
        }
      if (s.size() < 2)
        throw std::runtime_error("fewer than 2 rows in " + file);
      return s;
    };
    const auto run = series(csv), ref = series(reference);
    const double half = 0.5 * ref.back().second;
    const auto   arrival = [&](const std::vector<std::pair<double, double>> &s) {
      for (unsigned int k = 1; k < s.size(); ++k)
        if ((s[k].second - half) * (s[k - 1].second - half) <= 0 && s[k].second != s[k - 1].second)
          return s[k - 1].first +
                 (half - s[k - 1].second) / (s[k].second - s[k - 1].second) * (s[k].first - s[k - 1].first);
      throw std::runtime_error("the signal never reaches half of the reference's last value");
    };
    const double t_run = arrival(run), t_ref = arrival(ref);
    std::cout << std::setprecision(6) << "arrival of " << column << ": " << t_run << ", reference " << t_ref << "\n";
    check("  |arrival - reference| / reference", std::abs(t_run - t_ref) / t_ref,
          std::abs(t_run - t_ref) <= arrival_tol * t_ref, "<= " + str(arrival_tol));
    double worst = 0, peak = 0;
    for (const auto &p : ref)
      peak = std::max(peak, std::abs(p.second));
    for (const auto &p : run)
      {
        auto it = std::lower_bound(ref.begin(), ref.end(), std::make_pair(p.first, -1e300));
        if (it == ref.end())
          it = ref.end() - 1;
        if (it == ref.begin())
          it = ref.begin() + 1;
        const auto  &a = *(it - 1), &b = *it;
        const double r = a.second + (p.first - a.first) / (b.first - a.first) * (b.second - a.second);
        worst          = std::max(worst, std::abs(p.second - r));
      }
    check("  max |" + column + " - reference| / max |reference|", worst / peak, worst <= signal_tol * peak,
          "<= " + str(signal_tol));
  }

  void
  check_dissipation(const std::string &csv, const double peak_step, const double balance)
  {
    const auto rows = read_rows(csv);
    if (rows.empty() || !rows[0].count("material_dissipation"))
      throw std::runtime_error("no column material_dissipation in " + csv);
    const auto   peak = read_row(csv, peak_step);
    const double d    = peak.at("material_dissipation");
    double       work = 0, drop = 0, drift = 0, imbalance = 0;
    for (const auto &row : rows)
      work = std::max(work, std::abs(row.at("external_work")));
    for (unsigned int k = 0; k < rows.size(); ++k)
      {
        const auto  &row = rows[k];
        const double dk  = row.at("material_dissipation");
        if (k > 0)
          drop = std::max(drop, rows[k - 1].at("material_dissipation") - dk);
        if (row.at("step") > peak_step)
          drift = std::max(drift, std::abs(dk - d));
        imbalance = std::max(imbalance, std::abs(row.at("external_work") - row.at("strain_energy") -
                                                 row.at("kinetic_energy") - dk));
      }
    std::cout << std::setprecision(6) << "at step " << peak_step << ": external work " << peak.at("external_work")
              << ", strain energy " << peak.at("strain_energy") << ", material dissipation " << d << "\n";
    check("material dissipation at the peak / external work there", d / peak.at("external_work"), d > 0, "> 0");
    check("largest decrease of D from a row to the next / D at the peak", drop / d, drop <= 1e-12 * d, "<= 1e-12");
    check("max |D - D at the peak| after the peak / D at the peak", drift / d, drift <= 1e-12 * d, "<= 1e-12");
    check("max |W - strain - kinetic - D| / max |W|", imbalance / work, imbalance <= balance * work,
          "<= " + str(balance));
  }

  void
  check_modulus(const std::map<std::string, double> &row, const std::vector<std::string> &columns,
                const double area, const double reference, const double tol)
  {
    for (const auto &c : columns)
      if (!row.count(c))
        throw std::runtime_error("no column " + c);
    const double strain  = (row.at(columns[1]) - row.at(columns[0])) / (row.at(columns[3]) - row.at(columns[2]));
    const double stress  = row.at(columns[4]) / area;
    const double modulus = stress / strain;
    std::cout << std::setprecision(6) << "gauge length = " << row.at(columns[3]) - row.at(columns[2])
              << ", gauge strain = " << strain << ", stress = " << stress << "\n"
              << "Young's modulus = " << modulus << " (expected " << reference << ")\n";
    check("  |E / expected - 1|", std::abs(modulus / reference - 1), std::abs(modulus / reference - 1) <= tol,
          "<= " + str(tol));
  }

  // Newton histories: "Newton 0: |R| = r" starts a solve, "Newton i: |R| = r" continues it.
  void
  check_newton(const std::string &out, const unsigned int max_it, const double min_order)
  {
    std::ifstream in(out);
    if (!in)
      throw std::runtime_error("cannot open " + out);
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
      throw std::runtime_error("no Newton iterations in " + out);
    unsigned int most = 0, orders = 0;
    double       worst = 1e300;
    for (unsigned int s = 0; s < solves.size(); ++s)
      {
        const auto &r = solves[s];
        most          = std::max<unsigned int>(most, r.size() - 1);
        // Convergence histories only where the order is checked (below
        // round-off they differ between runs), of the first three solves.
        if (s < 3 && min_order > 0)
          {
            std::cout << "solve " << s + 1 << ": " << r.size() - 1 << " iterations, |R_k|/|R_0|:";
            for (unsigned int k = 1; k < r.size(); ++k)
              std::cout << " " << std::setprecision(2) << (r[k] > 1e-13 * r[0] ? r[k] / r[0] : 0.0);
            std::cout << "\n";
          }
        for (unsigned int k = 2; k < r.size(); ++k)
          if (r[k] > 1e-13 * r[0])
            {
              const double order = std::log(r[k] / r[k - 1]) / std::log(r[k - 1] / r[k - 2]);
              if (s < 3 && min_order > 0)
                std::cout << "  order at iteration " << k << ": " << std::setprecision(3) << order << "\n";
              worst = std::min(worst, order);
              ++orders;
            }
      }
    check("most Newton iterations in a solve", most, most <= max_it, "<= " + std::to_string(max_it));
    if (min_order > 0)
      {
        check("iterations above round-off with an order estimate", orders, orders > 0, "> 0");
        check("smallest convergence order", orders ? worst : 0, orders > 0 && worst >= min_order,
              ">= " + str(min_order));
      }
    std::cout << solves.size() << " solves\n";
  }
} // namespace

int
check_quasistatic(int argc, char *argv[])
{
  try
    {
      std::string              csv, out;
      double                   step = 0, scale = 1, tol = 0, min_order = 0, drift = -1;
      unsigned int             max_it = 0;
      std::vector<std::string> expected;
      std::string              reference, column;
      double                   arrival_tol = 0, signal_tol = 0, critical_stretch = 0;
      std::string              stretch_column, reaction_column;
      std::vector<std::string> modulus_columns;
      double                   area = 0, modulus = 0, modulus_tol = 0;
      struct Fraction
      {
        std::string column;
        double      min, max;
      };
      std::vector<Fraction> fractions;
      double                dissipation_peak = -1, dissipation_balance = 0;
      for (int a = 1; a < argc; ++a)
        {
          const std::string arg = argv[a];
          const auto        next = [&]() { return check_common::next_argument(argc, argv, a, arg); };
          if (arg == "--csv")
            csv = next();
          else if (arg == "--stdout")
            out = next();
          else if (arg == "--step")
            step = std::atof(next().c_str());
          else if (arg == "--scale")
            scale = std::atof(next().c_str());
          else if (arg == "--tol")
            tol = std::atof(next().c_str());
          else if (arg == "--min-order")
            min_order = std::atof(next().c_str());
          else if (arg == "--max-iterations")
            max_it = std::atoi(next().c_str());
          else if (arg == "--energy-drift")
            drift = std::atof(next().c_str());
          else if (arg == "--reference")
            reference = next();
          else if (arg == "--column")
            column = next();
          else if (arg == "--arrival-tol")
            arrival_tol = std::atof(next().c_str());
          else if (arg == "--signal-tol")
            signal_tol = std::atof(next().c_str());
          else if (arg == "--fracture")
            {
              critical_stretch = std::atof(next().c_str());
              stretch_column   = next();
              reaction_column  = next();
            }
          else if (arg == "--modulus")
            {
              for (unsigned int c = 0; c < 5; ++c)
                modulus_columns.push_back(next());
              area        = std::atof(next().c_str());
              modulus     = std::atof(next().c_str());
              modulus_tol = std::atof(next().c_str());
            }
          else if (arg == "--dissipation")
            {
              dissipation_peak    = std::atof(next().c_str());
              dissipation_balance = std::atof(next().c_str());
            }
          else if (arg == "--energy-fraction")
            {
              const std::string name = next();
              const double      lo   = std::atof(next().c_str());
              fractions.push_back({name, lo, std::atof(next().c_str())});
            }
          else if (arg.find('=') != std::string::npos)
            expected.push_back(arg);
          else
            throw std::runtime_error("unknown argument " + arg);
        }
      if (csv.empty())
        throw std::runtime_error("--csv is required");

      for (const auto &f : fractions)
        {
          const auto   first = read_row(csv, 0);
          const auto   row   = read_row(csv, step);
          if (!row.count(f.column))
            throw std::runtime_error("no column " + f.column);
          const double e0       = first.at("kinetic_energy") + first.at("strain_energy");
          const double fraction = 2 * row.at(f.column) / e0;
          check("2 " + f.column + " / initial energy at step " + str(step), fraction,
                fraction >= f.min && fraction <= f.max, "in [" + str(f.min) + ", " + str(f.max) + "]");
        }
      if (!expected.empty())
        {
          const auto row = read_row(csv, step);
          for (const auto &arg : expected)
            {
              const auto        eq       = arg.find('=');
              const std::string name     = arg.substr(0, eq);
              const double      expected = std::atof(arg.substr(eq + 1).c_str());
              double            value    = 0;
              for (std::size_t begin = 0, end; begin <= name.size(); begin = end + 1)
                {
                  end                      = std::min(name.find('+', begin), name.size());
                  const std::string column = name.substr(begin, end - begin);
                  if (!row.count(column))
                    throw std::runtime_error("no column " + column);
                  value += row.at(column);
                }
              std::cout << std::setprecision(10) << name << " = " << value << " (expected " << expected << ")\n";
              const double error = std::abs(value - expected) / scale;
              check("  |" + name + " - expected| / scale", error, error <= tol, "<= " + str(tol));
            }
        }

      if (drift >= 0)
        {
          const auto   first = read_row(csv, 0);
          const double e0    = first.at("kinetic_energy") + first.at("strain_energy");
          double       worst = 0;
          const bool converts = first.count("conversion_energy") > 0;
          for (const auto &row : read_rows(csv))
            worst = std::max(worst, std::abs(row.at("kinetic_energy") + row.at("strain_energy") -
                                             row.at("external_work") -
                                             (converts ? row.at("conversion_energy") : 0.0) - e0) / e0);
          check(converts ? "max |E - W - J - E0| / E0 (E = kinetic + strain, W external work, J conversion jumps)" :
                           "max |E - W - E0| / E0 (E = kinetic + strain, W external work)",
                worst, worst <= drift, "<= " + str(drift));
        }

      if (dissipation_peak >= 0)
        check_dissipation(csv, dissipation_peak, dissipation_balance);
      if (!modulus_columns.empty())
        check_modulus(read_row(csv, step), modulus_columns, area, modulus, modulus_tol);
      if (critical_stretch > 0)
        check_fracture(csv, critical_stretch, stretch_column, reaction_column);
      if (!reference.empty())
        compare_signals(csv, reference, column, arrival_tol, signal_tol);
      if (!out.empty())
        check_newton(out, max_it, min_order);
    }
  catch (const std::exception &e)
    {
      std::cout << "Error: " << e.what() << std::endl;
      return 2;
    }
  return check_common::finish();
}
