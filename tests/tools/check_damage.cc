// perideal_check softening: checks a pd_app run of one bond (two points 1
// apart, volume 1, PMB) under the Linear softening damage model against the
// bilinear bond law. Usage:
//   perideal_check softening CSV STDOUT s_0 s_c K horizon
// CSV columns: the globals and the computes ul, ur (the two points' u_x) and
// fr (the force on the right point, V f_x). With s = ur - ul, s_max the
// largest s so far (rows at every step), c = 18 K / (pi horizon^4) and
// d = s_c (s_max - s_0) / (s_max (s_c - s_0)) clamped to [0, 1]:
// - every row: fr = -(1 - d) c s, strain energy (1 - d) c s^2 / 2, max damage
//   d, broken bonds 1 once s_max >= s_c, else 0;
// - the rows on the loading envelope (s = s_max) beyond s_0: the bilinear
//   law's falling branch c s_0 (s_c - s) / (s_c - s_0), written without d;
// - unloading rows (s < s_max, s_0 < s_max < s_c): the secant through the
//   origin, fr / s = the envelope's force at s_max over s_max;
// - the largest force is c s_0 (at most, and within 1% of it: the stretch
//   nearest s_0 is sampled);
// - STDOUT: the summary's dissipated energy equals sum_k c s_k^2 / 2
//   (d_k - d_{k-1}) over the rows (what the damage released, credited at
//   each step's stretch) to 5e-6 (the summary prints 6 digits), and the
//   area under the bilinear curve c s_0 s_c / 2 to 0.5%; the energy balance
//   error below 0.5%. Crediting a step's rise of d at its end stretch
//   overestimates the area by about (step in s) / s per step: +0.30% with
//   the 4000 steps of softening_pair.prm, and the balance error is that.
// Prints the numbers with PASS/FAIL; non-zero exit on failure. Serial; no MPI.

#include "check.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace
{
  using check_common::check;

  /// The summary line "  NAME:   VALUE ..." of pd_app's standard output.
  double
  summary_value(const std::string &file, const std::string &name)
  {
    std::ifstream in(file);
    if (!in)
      throw std::runtime_error("cannot open " + file);
    for (std::string line; std::getline(in, line);)
      {
        const auto at = line.find(name + ":");
        if (at != std::string::npos)
          return std::stod(line.substr(at + name.size() + 1));
      }
    throw std::runtime_error("no '" + name + ":' line in " + file);
  }
} // namespace

int
check_damage(int argc, char *argv[])
{
  try
    {
      if (argc != 7)
        throw std::runtime_error("usage: perideal_check softening CSV STDOUT s_0 s_c K horizon");
      const auto   rows = check_common::read_rows(argv[1]);
      const double s0 = std::stod(argv[3]), sc = std::stod(argv[4]), K = std::stod(argv[5]),
                   delta = std::stod(argv[6]);
      const double c     = 18 * K / (M_PI * std::pow(delta, 4));
      const double peak  = c * s0; // the bilinear law's largest force
      const auto   law   = [&](const double s_max) {
        return s_max <= s0 ? 0.0 : s_max >= sc ? 1.0 : sc * (s_max - s0) / (s_max * (sc - s0));
      };
      const auto envelope = [&](const double s) { return s <= s0 ? c * s : s >= sc ? 0.0 : peak * (sc - s) / (sc - s0); };

      double s_max = 0, d_previous = 0, released = 0, largest = 0, s_at_largest = 0, closest = 1e300;
      double err_force = 0, err_energy = 0, err_damage = 0, err_envelope = 0, err_secant = 0, broken_force = 0;
      unsigned int bad_broken = 0, n_envelope = 0, n_secant = 0, n_broken = 0;
      for (const auto &r : rows)
        {
          const double s = r.at("ur") - r.at("ul");
          const double f = -r.at("fr");
          s_max          = std::max(s_max, s);
          closest        = std::min(closest, std::abs(s_max - sc) / sc);
          const double d = law(s_max);
          released += 0.5 * c * s * s * (d - d_previous);
          d_previous = d;
          err_force  = std::max(err_force, std::abs(f - (1 - d) * c * s) / peak);
          err_energy = std::max(err_energy, std::abs(r.at("strain_energy") - (1 - d) * 0.5 * c * s * s) / (0.5 * peak * s0));
          err_damage = std::max(err_damage, std::abs(r.at("max_damage") - d));
          bad_broken += r.at("broken_bonds") != (d == 1 ? 1 : 0);
          if (f > largest)
            largest = f, s_at_largest = s;
          if (d == 1)
            broken_force = std::max(broken_force, std::abs(f)), ++n_broken;
          else if (s == s_max && s > s0)
            err_envelope = std::max(err_envelope, std::abs(f - envelope(s)) / peak), ++n_envelope;
          else if (s < s_max && s_max > s0 && s > 0)
            err_secant = std::max(err_secant, std::abs(f - s * envelope(s_max) / s_max) / peak), ++n_secant;
        }
      std::cout << rows.size() << " rows; " << n_envelope << " on the softening envelope, " << n_secant
                << " unloading or reloading below the largest stretch, " << n_broken << " broken\n";
      check("max |f - (1 - d) c s| / (c s_0)", err_force, err_force < 1e-8, "< 1e-8", 3);
      check("max |W - (1 - d) c s^2/2| / (c s_0^2/2)", err_energy, err_energy < 1e-8, "< 1e-8", 3);
      check("max |point damage - d|", err_damage, err_damage < 1e-8, "< 1e-8", 3);
      check("rows whose broken_bonds differs from s_max >= s_c", bad_broken, bad_broken == 0, "== 0", 3);
      check("max |f - c s_0 (s_c - s)/(s_c - s_0)| / (c s_0) on the envelope", err_envelope,
            err_envelope < 1e-8 && n_envelope > 100, "< 1e-8, over > 100 rows", 3);
      check("max |f - s f_env(s_max)/s_max| / (c s_0) unloading (secant)", err_secant,
            err_secant < 1e-8 && n_secant > 100, "< 1e-8, over > 100 rows", 3);
      check("largest force / (c s_0)", largest / peak, largest <= peak * (1 + 1e-9) && largest > 0.99 * peak,
            "in (0.99, 1]", 6);
      check("stretch at the largest force / s_0", s_at_largest / s0, std::abs(s_at_largest / s0 - 1) < 0.02,
            "within 2% of 1: the peak is at s_0", 6);
      check("max |f| once broken / (c s_0)", broken_force / peak, broken_force == 0 && n_broken > 0,
            "== 0, over some rows", 3);
      check("closest approach of s_max to s_c, relative", closest, closest > 1e-6,
            "> 1e-6: the break row does not hinge on round-off", 3);

      const double dissipated = summary_value(argv[2], "dissipated energy");
      const double balance    = summary_value(argv[2], "energy balance error");
      const double area       = 0.5 * c * s0 * sc;
      check("dissipated / sum of c s^2/2 (d_k - d_k-1) - 1", dissipated / released - 1,
            std::abs(dissipated / released - 1) < 5e-6, "|.| < 5e-6", 3);
      check("dissipated / (c s_0 s_c / 2) - 1", dissipated / area - 1, std::abs(dissipated / area - 1) < 5e-3,
            "|.| < 5e-3: the area under the bilinear curve", 3);
      check("energy balance error", balance, std::abs(balance) < 5e-3, "|.| < 5e-3: the dissipation's bias", 3);
    }
  catch (const std::exception &e)
    {
      std::cout << "error: " << e.what() << std::endl;
      return 2;
    }
  return check_common::finish();
}
