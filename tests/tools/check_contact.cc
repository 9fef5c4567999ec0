// perideal_check contact --csv CSV [--duration T --tol-duration R]
//                        [--final NAME=VALUE ... --tol-final R]
//                        [--final-below NAME=VALUE ...] [--final-above NAME=VALUE ...]
//                        [--peak NAME=VALUE ... --tol-peak R]
//                        [--conserved NAME=S ... --tol-conserved R]
//                        [--energy R]
// Checks of a contact run's globals CSV written at every step:
// - --duration: the time the contact lasted (the rows with contact_energy > 0:
//   last - first + one step, the step the time between two rows) against T,
//   relative |measured - T| / T <= R;
// - --final: the last row's NAME against VALUE, relative to |VALUE|, <= R;
//   --final-below: |NAME| <= VALUE in the last row; --final-above: NAME >= VALUE;
// - --peak: the largest |NAME| over the rows against |VALUE|, relative, <= R;
// - --conserved: every row's NAME minus the first row's, over S, <= R
//   (momentum: S the initial momentum of one body);
// - --energy: every row's kinetic + strain + contact_energy +
//   contact_dissipation - external_work against the first row's, relative
//   to it, <= R.
#include "check.h"

#include <algorithm>
#include <cmath>

using namespace check_common;

int
check_contact(int argc, char *argv[])
{
  try
    {
      std::string                                 csv;
      double                                      duration = -1, tol_duration = 0, tol_final = 0, tol_conserved = 0,
             tol_energy = -1, tol_peak = 0;
      std::vector<std::pair<std::string, double>> finals, conserved, below, above, peaks;
      const auto                                  name_value = [](const std::string &v, const std::string &option) {
        const auto eq = v.find('=');
        if (eq == std::string::npos)
          throw std::runtime_error(option + " needs NAME=VALUE");
        return std::make_pair(v.substr(0, eq), std::stod(v.substr(eq + 1)));
      };
      for (int a = 1; a < argc; ++a)
        {
          const std::string arg = argv[a];
          if (arg == "--csv")
            csv = next_argument(argc, argv, a, arg);
          else if (arg == "--duration")
            duration = std::stod(next_argument(argc, argv, a, arg));
          else if (arg == "--tol-duration")
            tol_duration = std::stod(next_argument(argc, argv, a, arg));
          else if (arg == "--final")
            finals.push_back(name_value(next_argument(argc, argv, a, arg), arg));
          else if (arg == "--final-below")
            below.push_back(name_value(next_argument(argc, argv, a, arg), arg));
          else if (arg == "--final-above")
            above.push_back(name_value(next_argument(argc, argv, a, arg), arg));
          else if (arg == "--peak")
            peaks.push_back(name_value(next_argument(argc, argv, a, arg), arg));
          else if (arg == "--tol-peak")
            tol_peak = std::stod(next_argument(argc, argv, a, arg));
          else if (arg == "--tol-final")
            tol_final = std::stod(next_argument(argc, argv, a, arg));
          else if (arg == "--conserved")
            conserved.push_back(name_value(next_argument(argc, argv, a, arg), arg));
          else if (arg == "--tol-conserved")
            tol_conserved = std::stod(next_argument(argc, argv, a, arg));
          else if (arg == "--energy")
            tol_energy = std::stod(next_argument(argc, argv, a, arg));
          else
            throw std::runtime_error("unknown argument " + arg);
        }
      const std::vector<Row> rows = read_rows(csv);
      if (rows.size() < 3 || !rows[0].count("contact_energy"))
        throw std::runtime_error(csv + ": fewer than 3 rows or no column contact_energy");
      if (duration > 0)
        {
          int first = -1, last = -1;
          for (unsigned int k = 0; k < rows.size(); ++k)
            if (rows[k].at("contact_energy") > 0)
              {
                if (first < 0)
                  first = k;
                last = k;
              }
          const double step     = rows[1].at("time") - rows[0].at("time");
          const double measured = first < 0 ? 0 : rows[last].at("time") - rows[first].at("time") + step;
          std::cout << "contact from t = " << str(first < 0 ? 0 : rows[first].at("time"), 6) << " to "
                    << str(last < 0 ? 0 : rows[last].at("time"), 6) << "\n";
          check("contact duration", measured, first >= 0 && std::abs(measured - duration) <= tol_duration * duration,
                "expected " + str(duration, 8) + ", relative tolerance " + str(tol_duration), 8);
        }
      for (const auto &[name, value] : finals)
        {
          const double got = rows.back().at(name);
          check(name, got, std::abs(got - value) <= tol_final * std::abs(value),
                "expected " + str(value, 8) + ", relative tolerance " + str(tol_final), 10);
        }
      for (const auto &[name, value] : peaks)
        {
          double got = 0;
          for (const Row &row : rows)
            got = std::max(got, std::abs(row.at(name)));
          check("max |" + name + "|", got, std::abs(got - std::abs(value)) <= tol_peak * std::abs(value),
                "expected " + str(std::abs(value), 8) + ", relative tolerance " + str(tol_peak), 8);
        }
      for (const auto &[name, value] : below)
        {
          const double got = rows.back().at(name);
          check("|" + name + "|", std::abs(got), std::abs(got) <= value, "<= " + str(value, 8), 6);
        }
      for (const auto &[name, value] : above)
        {
          const double got = rows.back().at(name);
          check(name, got, got >= value, ">= " + str(value, 8), 6);
        }
      for (const auto &[name, scale] : conserved)
        {
          double worst = 0;
          for (const Row &row : rows)
            worst = std::max(worst, std::abs(row.at(name) - rows[0].at(name)) / scale);
          check("max |" + name + " - initial| / " + str(scale), worst, worst <= tol_conserved,
                "<= " + str(tol_conserved), 3);
        }
      if (tol_energy >= 0)
        {
          const auto total = [](const Row &r) {
            return r.at("kinetic_energy") + r.at("strain_energy") + r.at("contact_energy") +
                   r.at("contact_dissipation") - r.at("external_work");
          };
          const double E0    = total(rows[0]);
          double       worst = 0;
          for (const Row &row : rows)
            worst = std::max(worst, std::abs(total(row) - E0) / std::abs(E0));
          check("max |E - E0| / E0 (E = kinetic + strain + contact + friction work - external work)", worst,
                worst <= tol_energy, "<= " + str(tol_energy), 3);
        }
      return finish();
    }
  catch (const std::exception &e)
    {
      std::cout << "error: " << e.what() << std::endl;
      return 2;
    }
}
