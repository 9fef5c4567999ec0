// perideal_check globals: checks the globals CSV of a pd_app run (step,time,
// kinetic_energy,strain_energy,external_work,broken_bonds,max_damage) against
// analytic answers. Usage:
//   perideal_check globals verlet  CSV pd_app-stdout
//   perideal_check globals blowup  CSV pd_app-stderr steps-asked
//   perideal_check globals pair    CSV A T s_c K horizon [rate]
//   perideal_check globals split   CSV nx ny nz Lx Ly Lz horizon x_split D T s_c K (0: no energy check) [rate]
// (split, PMB: the strain energy and, if the CSV has released_energy, the
// energy released so far, each bond's c s^2 |xi| V^2 / 2 at the row it broke)
//   perideal_check globals split_energy CSV nx ny nz Lx Ly Lz horizon x_split D T G_c K
//   perideal_check globals crack_tip CSV nx ny nz Lx Ly Lz horizon v eps s_c threshold window
// (rate: the critical stretch is s_c + rate t, Time dependent critical stretch.
// split_energy: Critical energy on PMB, each bond's critical stretch
// sqrt(4 G_c / (9 K |xi|)), where c s^2 |xi| / 2 reaches 4 G_c / (pi delta^4).)
// Prints the measured numbers with PASS/FAIL and returns non-zero on failure.
// Serial; no MPI.

#include "check.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
  struct Row
  {
    double step, time, kinetic, strain, work, broken, damage;
    double released = std::nan(""); // the column released_energy, if there
  };

  std::vector<Row>
  read_csv(const std::string &file)
  {
    std::ifstream in(file);
    if (!in)
      throw std::runtime_error("cannot open " + file);
    std::string header;
    std::getline(in, header);
    // The columns read; a model with dissipation adds material_dissipation after them.
    const std::string columns = "step,time,kinetic_energy,strain_energy,external_work,broken_bonds,max_damage";
    if (header != columns && header.rfind(columns + ",", 0) != 0)
      throw std::runtime_error("unexpected header in " + file + ": " + header);
    // Solver/Track dissipated energy adds released_energy after them.
    int released_column = -1;
    {
      std::istringstream names(header);
      std::string        name;
      for (int k = 0; std::getline(names, name, ','); ++k)
        if (name == "released_energy")
          released_column = k;
    }
    std::vector<Row> rows;
    std::string      line;
    while (std::getline(in, line))
      {
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream s(line);
        Row                r;
        s >> r.step >> r.time >> r.kinetic >> r.strain >> r.work >> r.broken >> r.damage;
        for (int k = 7; k <= released_column && s; ++k)
          s >> r.released;
        if (!s)
          throw std::runtime_error("bad line in " + file + ": " + line);
        rows.push_back(r);
      }
    if (rows.empty())
      throw std::runtime_error("no rows in " + file);
    return rows;
  }

  void
  check(const std::string &name, const double value, const bool ok, const std::string &bound)
  {
    std::cout << std::setprecision(8); // later lines print with it, as they always did
    check_common::check(name, value, ok, bound, 8);
  }

  std::string
  str(const double v)
  {
    return check_common::str(v, 6);
  }

  /// The points of a Box discretization from the origin: the centres of its
  /// nx x ny x nz cells of hx x hy x hz, x fastest.
  std::vector<std::array<double, 3>>
  cell_centres(const unsigned int nx, const unsigned int ny, const unsigned int nz, const double hx, const double hy,
               const double hz)
  {
    std::vector<std::array<double, 3>> X;
    for (unsigned int k = 0; k < nz; ++k)
      for (unsigned int j = 0; j < ny; ++j)
        for (unsigned int i = 0; i < nx; ++i)
          X.push_back({{(i + 0.5) * hx, (j + 0.5) * hy, (k + 0.5) * hz}});
    return X;
  }

  double
  total(const Row &r)
  {
    return r.kinetic + r.strain;
  }
} // namespace

int
check_globals(int argc, char *argv[])
{
  try
    {
      if (argc < 3)
        throw std::runtime_error("usage: perideal_check globals MODE CSV ...");
      const std::string         mode = argv[1];
      const std::vector<Row>    rows = read_csv(argv[2]);
      std::vector<double>       a;
      for (int i = 3; i < argc; ++i)
        a.push_back(std::atof(argv[i]));
      auto need = [&](const std::size_t n, const std::size_t optional = 0) {
        if (a.size() < n || a.size() > n + optional)
          throw std::runtime_error(mode + " needs " + std::to_string(n) +
                                   (optional ? " to " + std::to_string(n + optional) : std::string()) +
                                   " numbers after the CSV");
      };
      std::cout << rows.size() << " rows, last step " << rows.back().step << "\n";

      if (mode == "verlet")
        {
          // Velocity-Verlet on a linear system keeps, per mode k,
          //   Q_k = v_k^2 + omega_k^2 (1 - (omega_k dt/2)^2) u_k^2
          // exactly. Started from u = 0, E0 = sum Q_k / 2 and
          //   E(t) - E0 = sum_k (omega_k dt/2)^2 SE_k(t),
          // so 0 <= E(t) - E0 <= (omega_max dt/2)^2 SE(t) <= (dt/dt_est)^2 SE(t)
          // when dt_est <= 2/omega_max (a conservative estimate). A force that
          // is not minus the gradient of the reported energy, an energy off by
          // a factor, or a first-order integrator breaks this within a few steps.
          // dt and dt_est are read from pd_app's set-up report.
          if (argc != 4)
            throw std::runtime_error("verlet needs the pd_app stdout after the CSV");
          std::ifstream out(argv[3]);
          std::string   line;
          double        dt = 0, dt_est = 0;
          while (std::getline(out, line))
            {
              std::istringstream s(line);
              std::string        w1, w2, w3;
              s >> w1 >> w2;
              if (w1 == "stable" && w2 == "time")
                s >> w3 >> dt_est;
              else if (w1 == "time" && w2 == "step:")
                s >> dt;
            }
          if (!(dt > 0 && dt_est > 0))
            throw std::runtime_error("no 'stable time step' and 'time step' lines in " + std::string(argv[3]));
          const double bound = (dt / dt_est) * (dt / dt_est);
          const double E0    = total(rows.front());
          // (E - E0) / SE per output step after the first; 1e-6 allows for round-off
          // and the geometric nonlinearity (amplitudes ~1e-6).
          double lo = 1e300, hi = -1e300, damage = 0;
          for (const auto &r : rows)
            {
              damage = std::max(damage, r.broken + r.damage);
              if (r.step == 0)
                continue;
              if (!(r.strain > 0))
                throw std::runtime_error("no strain energy at step " + std::to_string(r.step));
              lo = std::min(lo, (total(r) - E0) / r.strain);
              hi = std::max(hi, (total(r) - E0) / r.strain);
            }
          const double drift = (total(rows.back()) - E0) / E0;
          double       max_dev = 0;
          for (const auto &r : rows)
            max_dev = std::max(max_dev, std::abs(total(r) - E0) / E0);
          std::cout << std::setprecision(6) << "dt / dt_est = " << dt / dt_est << "\n";
          check("min (E - E0) / SE", lo, lo > -1e-6, "> -1e-6: E >= E0");
          check("max (E - E0) / SE", hi, hi < bound + 1e-6, "< (dt/dt_est)^2 = " + str(bound));
          // With SE <= E the above gives (E - E0)/E0 <= b/(1 - b), b = (dt/dt_est)^2.
          const double rel = bound / (1 - bound);
          check("relative drift (E_end - E0) / E0", drift, std::abs(drift) <= rel + 1e-6,
                "|.| <= b/(1-b) = " + str(rel) + ", b = (dt/dt_est)^2");
          check("max |E - E0| / E0", max_dev, max_dev <= rel + 1e-6, "<= b/(1-b) = " + str(rel));
          check("broken bonds + max damage", damage, damage == 0, "== 0: no damage model");
        }
      else if (mode == "blowup")
        {
          // pd_app stopped on blow-up: its Error names the step N; the globals
          // CSV then ends with the last good state, step N - 1, all finite.
          if (argc != 5)
            throw std::runtime_error("blowup needs the pd_app stderr and the number of steps asked for");
          std::ifstream     err(argv[3]);
          const std::string text((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
          const auto        at = text.find(" at step ");
          if (text.find("Error: ") == std::string::npos || at == std::string::npos)
            throw std::runtime_error("no 'Error: ... at step N' in " + std::string(argv[3]));
          const double step = std::atof(text.c_str() + at + 9);
          const double asked = std::atof(argv[4]);
          bool         finite = true;
          for (const auto &r : rows)
            for (const double v : {r.step, r.time, r.kinetic, r.strain, r.work, r.broken, r.damage})
              finite &= std::isfinite(v);
          std::cout << "stopped at step " << step << " of " << asked << "\n";
          check("stop step", step, step >= 1 && step < asked, "in [1, steps asked)");
          check("last CSV row", rows.back().step, rows.back().step == step - 1, "== stop step - 1: last good state");
          check("CSV values finite", finite, finite, "== 1");
        }
      else if (mode == "pair")
        {
          // Two points 1 apart, volume 1, u_x = -+A sin(pi t/T): stretch
          // s = 2 A sin(pi t / T). The bond breaks at the first step with
          // s > s_c and stays broken; PMB strain energy of the intact bond
          // (both halves) is c s^2 |xi| V^2 / 2 with c = 18 K / (pi delta^4).
          need(5, 1);
          const double A = a[0], T = a[1], sc = a[2], K = a[3], delta = a[4], rate = a.size() > 5 ? a[5] : 0;
          const double c = 18 * K / (M_PI * std::pow(delta, 4));
          double       closest = 1e300;
          bool         broken  = false;
          int          break_step = -1;
          unsigned int bad_broken = 0, bad_damage = 0;
          double       bad_energy = 0;
          for (const auto &r : rows)
            {
              const double s = 2 * A * std::sin(M_PI * r.time / T), sc_t = sc + rate * r.time;
              closest = std::min(closest, std::abs(s - sc_t));
              broken |= s > sc_t;
              if (broken && break_step < 0)
                break_step = int(r.step);
              bad_broken += r.broken != (broken ? 1 : 0);
              bad_damage += r.damage != (broken ? 1 : 0);
              const double energy = broken ? 0 : 0.5 * c * s * s;
              bad_energy = std::max(bad_energy, std::abs(r.strain - energy) / (0.5 * c * sc * sc));
            }
          int csv_break = -1;
          for (const auto &r : rows)
            if (r.broken > 0 && csv_break < 0)
              csv_break = int(r.step);
          std::cout << "predicted break at step " << break_step << ", first broken row at step "
                    << csv_break << "; rows run to s = " << 2 * A * std::sin(M_PI * rows.back().time / T)
                    << "\n";
          check("rows whose broken_bonds differs from the prediction", bad_broken, bad_broken == 0, "== 0");
          check("rows whose max_damage differs from the prediction", bad_damage, bad_damage == 0, "== 0");
          check("max |strain energy - c s^2/2| / (c s_c^2/2)", bad_energy, bad_energy < 1e-9, "< 1e-9");
          check("broken bonds at the end (bond back at zero or compressed)", rows.back().broken,
                rows.back().broken == 1, "== 1: stays broken");
          check("break step", csv_break, csv_break == break_step && break_step > 0, "== predicted");
          check("closest approach of the stretch to s_c, relative", closest / sc, closest / sc > 1e-6,
                "> 1e-6: the prediction does not hinge on round-off");
        }
      else if (mode == "split" || mode == "split_energy")
        {
          // A box of nx x ny x nz cells; the points with x < x_split stay put,
          // the others are moved rigidly by d(t) = D sin(pi t / T) along x. A
          // bond i (left) - j (right) has stretch (|xi + d e_x| - |xi|)/|xi| and
          // breaks for good when it exceeds s_c; bonds within a half never
          // stretch. Point damage is the broken share of the family (uniform
          // volumes); strain energy (PMB) sums c s^2 |xi| V^2 / 2 over intact
          // bonds (K = 0: not checked, for the other models).
          need(12, 1);
          const unsigned int nx = a[0], ny = a[1], nz = a[2];
          const bool         by_energy = mode == "split_energy";
          const double       Lx = a[3], Ly = a[4], Lz = a[5], delta = a[6], xs = a[7], D = a[8], T = a[9],
                       K = a[11], rate = a.size() > 12 ? a[12] : 0;
          if (by_energy && !(K > 0))
            throw std::runtime_error("split_energy needs K > 0");
          // By energy: the scale below takes the critical stretch of a bond of length delta.
          const double sc = by_energy ? std::sqrt(4 * a[10] / (9 * K * delta)) : a[10];
          const double hx = Lx / nx, hy = Ly / ny, hz = Lz / nz, V = hx * hy * hz;
          const double c  = 18 * K / (M_PI * std::pow(delta, 4));
          const auto X = cell_centres(nx, ny, nz, hx, hy, hz);
          struct Bond
          {
            unsigned int i, j;
            double       ex, ey, ez, r0;
          };
          std::vector<Bond>         crossing;
          std::vector<unsigned int> family(X.size(), 0);
          const double              reach = delta * (1 + 1e-9);
          for (unsigned int i = 0; i < X.size(); ++i)
            for (unsigned int j = 0; j < X.size(); ++j)
              {
                const double ex = X[j][0] - X[i][0], ey = X[j][1] - X[i][1], ez = X[j][2] - X[i][2];
                const double r0 = std::sqrt(ex * ex + ey * ey + ez * ez);
                if (i == j || r0 > reach)
                  continue;
                ++family[i];
                if (X[i][0] < xs && X[j][0] > xs)
                  crossing.push_back({i, j, ex, ey, ez, r0});
              }
          std::cout << crossing.size() << " bonds cross x = " << xs << "\n";
          std::vector<char> broken(crossing.size(), 0);
          unsigned int      bad_broken = 0, bad_damage = 0, max_count = 0;
          double            bad_energy = 0, d_max = 0, closest = 1e300;
          // Released: each bond's energy c s^2 |xi| V^2 / 2 at the row where it broke.
          double released = 0, bad_released = 0;
          for (const auto &r : rows)
            {
              const double d = D * std::sin(M_PI * r.time / T), sc_t = sc + rate * r.time;
              d_max          = std::max(d_max, d);
              double       energy = 0;
              unsigned int count  = 0;
              std::vector<unsigned int> broken_of(X.size(), 0);
              for (unsigned int b = 0; b < crossing.size(); ++b)
                {
                  const Bond  &e = crossing[b];
                  const double r = std::sqrt((e.ex + d) * (e.ex + d) + e.ey * e.ey + e.ez * e.ez);
                  const double s    = (r - e.r0) / e.r0;
                  const double sc_b = by_energy ? std::sqrt(4 * a[10] / (9 * K * e.r0)) : sc_t;
                  // Relative to each bond's own limit, scaled as the printed line divides by sc.
                  closest = std::min(closest, by_energy ? std::abs(s - sc_b) / sc_b * sc : std::abs(s - sc_t));
                  if (!broken[b] && s > sc_b)
                    {
                      broken[b] = 1;
                      released += 0.5 * c * s * s * e.r0 * V * V;
                    }
                  if (broken[b])
                    ++count, ++broken_of[e.i], ++broken_of[e.j];
                  else
                    energy += 0.5 * c * s * s * e.r0 * V * V;
                }
              double damage = 0;
              for (unsigned int p = 0; p < X.size(); ++p)
                damage = std::max(damage, double(broken_of[p]) / family[p]);
              max_count = std::max(max_count, count);
              bad_broken += r.broken != count;
              // The CSV holds 10 significant digits.
              bad_damage += std::abs(r.damage - damage) > 1e-9;
              const double scale = 0.5 * c * sc * sc * V * V * crossing.size() * delta;
              bad_energy         = std::max(bad_energy, std::abs(r.strain - energy) / scale);
              if (!std::isnan(r.released))
                bad_released = std::max(bad_released, std::abs(r.released - released) / scale);
            }
          std::cout << "broken bonds predicted at the end: " << max_count << " of " << crossing.size()
                    << " crossing; max opening " << d_max << "\n";
          check("closest approach of a bond stretch to s_c, relative", closest / sc, closest / sc > 1e-6,
                "> 1e-6: the prediction does not hinge on round-off");
          check("rows whose broken_bonds differs from the prediction", bad_broken, bad_broken == 0, "== 0");
          check("rows whose max_damage differs from the prediction", bad_damage, bad_damage == 0,
                "== 0 (|diff| > 1e-9)");
          if (K > 0)
            check("max |strain energy - prediction| / (c s_c^2 V^2 delta n_crossing / 2)", bad_energy,
                  bad_energy < 1e-9, "< 1e-9");
          else
            std::cout << "strain energy not predicted (K = 0: a model other than PMB)\n";
          if (K > 0 && !std::isnan(rows.back().released))
            check("max |released_energy - prediction| / (c s_c^2 V^2 delta n_crossing / 2)", bad_released,
                  bad_released < 1e-9 && released > 0, "< 1e-9");
          check("broken bonds at the end", rows.back().broken,
                rows.back().broken == max_count && max_count > 0 && max_count < crossing.size(),
                "== predicted, some but not all crossing bonds");
        }
      else if (mode == "crack_tip")
        {
          // A box of nx x ny x nz cells; at the time t of a row every point
          // with x < v t has the displacement (0, eps y, 0), the others none.
          // A bond breaks for good at the first row (every step is one) where
          // its stretch passes s_c; point damage is the broken share of its
          // family (uniform volumes). The columns tip and tip_step (Crack tip,
          // direction +x from the origin) must be the farthest x of a point
          // with damage >= threshold (0 without one), and their rates the
          // least-squares slope of those predictions over the rows of the
          // last `window` time (tip_rate) and over the last two rows
          // (tip_step_rate).
          need(12);
          const unsigned int nx = a[0], ny = a[1], nz = a[2];
          const double       Lx = a[3], Ly = a[4], Lz = a[5], delta = a[6], v = a[7], eps = a[8], sc = a[9],
                       threshold = a[10], window = a[11];
          const double hx = Lx / nx, hy = Ly / ny, hz = Lz / nz;
          const auto X = cell_centres(nx, ny, nz, hx, hy, hz);
          std::vector<std::array<unsigned int, 2>> bonds;
          std::vector<unsigned int>                family(X.size(), 0);
          for (unsigned int i = 0; i < X.size(); ++i)
            for (unsigned int j = i + 1; j < X.size(); ++j)
              {
                double r2 = 0;
                for (unsigned int d = 0; d < 3; ++d)
                  r2 += (X[j][d] - X[i][d]) * (X[j][d] - X[i][d]);
                if (std::sqrt(r2) <= delta * (1 + 1e-9))
                  bonds.push_back({{i, j}}), ++family[i], ++family[j];
              }
          const auto table = check_common::read_rows(argv[2]);
          std::vector<char>   broken(bonds.size(), 0);
          std::vector<double> times, tips;
          double              closest = 1e300, worst_tip = 0, worst_rate = 0, worst_step_rate = 0;
          for (const auto &row : table)
            {
              const double t = row.at("time");
              std::vector<unsigned int> broken_of(X.size(), 0);
              for (unsigned int b = 0; b < bonds.size(); ++b)
                {
                  const auto  &X0 = X[bonds[b][0]], &X1 = X[bonds[b][1]];
                  const double u0 = X0[0] < v * t ? eps * X0[1] : 0, u1 = X1[0] < v * t ? eps * X1[1] : 0;
                  double       r0 = 0, r = 0;
                  for (unsigned int d = 0; d < 3; ++d)
                    {
                      const double xi = X1[d] - X0[d], y = xi + (d == 1 ? u1 - u0 : 0);
                      r0 += xi * xi;
                      r += y * y;
                    }
                  const double s = std::sqrt(r / r0) - 1;
                  closest        = std::min(closest, std::abs(s - sc));
                  broken[b] |= s > sc;
                  if (broken[b])
                    ++broken_of[bonds[b][0]], ++broken_of[bonds[b][1]];
                }
              double tip = 0;
              for (unsigned int p = 0; p < X.size(); ++p)
                if (double(broken_of[p]) / family[p] >= threshold)
                  tip = std::max(tip, X[p][0]);
              times.push_back(t);
              tips.push_back(tip);
              // The least-squares slope over the rows from time `from` on (at least the last two).
              const auto slope = [&](const double from) {
                std::size_t first = times.size() - 1;
                while (first > 0 && (times[first - 1] >= from - 1e-9 * window || first + 1 == times.size()))
                  --first;
                const double n  = times.size() - first;
                double       mt = 0, mq = 0, stt = 0, stq = 0;
                for (std::size_t k = first; k < times.size(); ++k)
                  mt += times[k] / n, mq += tips[k] / n;
                for (std::size_t k = first; k < times.size(); ++k)
                  stt += (times[k] - mt) * (times[k] - mt), stq += (times[k] - mt) * (tips[k] - mq);
                return stt > 0 ? stq / stt : 0.0;
              };
              worst_tip = std::max({worst_tip, std::abs(row.at("tip") - tip), std::abs(row.at("tip_step") - tip)});
              worst_rate = std::max(worst_rate, std::abs(row.at("tip_rate") - slope(t - window)));
              worst_step_rate = std::max(worst_step_rate, std::abs(row.at("tip_step_rate") - slope(t)));
            }
          const double t_end = times.back(), tip_end = tips.back();
          std::cout << bonds.size() << " bonds; predicted tip at t = " << t_end << ": " << tip_end
                    << " (v t = " << v * t_end << ")\n";
          check("closest approach of a bond stretch to s_c", closest, closest > 1e-6 * sc,
                "> 1e-6 s_c: the prediction does not hinge on round-off");
          check("max |tip - prediction| (tip, tip_step)", worst_tip, worst_tip < 1e-9, "< 1e-9");
          check("max |tip_rate - least-squares slope over the window|", worst_rate, worst_rate < 1e-6 * v,
                "< 1e-6 v");
          check("max |tip_step_rate - slope of the last two rows|", worst_step_rate, worst_step_rate < 1e-6 * v,
                "< 1e-6 v");
          // The tip runs with the opening, a fixed distance ahead of or behind it.
          check("tip at the end - v t", tip_end - v * t_end, std::abs(tip_end - v * t_end) < delta,
                "within one horizon");
          check("last tip_rate / v", table.back().at("tip_rate") / v,
                std::abs(table.back().at("tip_rate") / v - 1) < 0.1, "within 10%");
        }
      else
        throw std::runtime_error("unknown mode " + mode);
    }
  catch (const std::exception &e)
    {
      std::cout << "Error: " << e.what() << std::endl;
      return 2;
    }
  return check_common::finish();
}
