// Conformance of every registered material: `models_conformance NAME` checks
// the material NAME of Registry<Material>, `models_conformance --list` lists
// them (tests/models/CMakeLists.txt makes models.NAME.np1/np2 from the list,
// so no material is named here or there).
//
// Parameters, found generically: the model's keys are declared into a
// ParameterHandler; Density gets rho = 1.3, Yield stress 1000 (the defaults
// variant stays elastic) and the moduli the first of
// {Bulk modulus}, {Bulk modulus, Shear modulus}, {Young's modulus, Poisson's
// ratio} (K = 2.5, G = 1.1, nu = 0.31) that the model declares and accepts
// (a bond-based model takes K alone, its nu being 1/4); every other key keeps
// its default. If the model cannot be
// created so, the material FAILS with the error and the keys left at their
// default (give the key a valid default, or teach the suite the key here).
// Variants: the defaults, then each other value of every Patterns::Selection
// key the model declares, and of the options in known_options() (LPS's
// Influence function is free text: '1 - r' is tried), one key at a time.
//
// Checks per variant, the plumbing in pdtest::Harness (tests/physics/
// harness.h: initialize, ghosts, compute_stage, compute_force), the force
// scale f_ref = K 1e-3 / horizon (a strain of 1e-3 over one horizon) and the
// energy scale K 1e-6:
// (a) rigid translation by O(1), box 8x7x5 (unequal spacings, off the origin):
//     max |f| / f_ref and max |W| / (K 1e-6) below 1e-10 at every point,
//     surface included. A rigid motion keeps every bond length; round-off in
//     y_j - y_i is ~1e-16 of |y| ~ 1, a stretch of ~1e-15 against 1e-3: four
//     orders of margin, while a real force (a missing term, a wrong sign of
//     u) is O(1).
// (b) rotations by 90 deg and by 1e-3 rad about the line through (0.9, 0.5,
//     -0.2) along (1, -2, 3) (points move by O(1)): the same bounds.
//     Objectivity: a non-affine state y0 (|grad u| ~ 1e-2) and Q y0 + c must
//     give f1 = Q f0 and W1 = W0 at every point, same bounds (a force along
//     the reference bond xi, not the deformed one, fails only this).
// (c) homogeneous u = H X, H general and not symmetric, |H| ~ 1e-4, cube
//     14^3, horizon 3.015 h: at the points deeper than 2 horizons, whose
//     family and neighbors' families are complete, every bond has a mirror
//     with the same extension and moduli, so the force cancels: max |f| /
//     f_ref below 1e-10 (round-off, as in (a)). If the model writes an energy
//     density there, W / (K tr(eps)^2/2 + G dev(eps):dev(eps)) with the
//     model's own K and G (PMB: G = 3K/5) is 1 within 0.2: the family is a
//     cubic lattice of ~123 cells, not a ball, so the sums differ from the
//     continuum's integrals (PMB: sum |xi| V = 1.099 pi delta^4) and the
//     material is cubic (LPS: C11 - C12 is 16.5% below 2G and C44 11% above G
//     at this horizon, physics/lps_homogeneous; its Surface correction, fitted
//     to the shears xy, yz, zx, scales G by ~0.9 even deep inside). Measured
//     0.89 to 1.04; a wrong calibration (a factor 2, a power of the horizon)
//     is far outside.
// (d) if add_tangent() returns true: the tangent against central finite
//     differences of the force (Tangent::add_finite_differences, epsilon =
//     1e-6 h) on a random state of 5% of the spacing (the geometric
//     stiffness matters), box 6x4x4, horizon 2.015 h: max |K - K_fd| / max
//     |K| below 1e-6 (truncation ~1e-12, round-off ~1e-9), at dt = 0.3 (a
//     rate model's history moves with the state). Without an
//     analytic tangent the output says so (the solvers then use finite
//     differences); that is no failure.
// (e) the stable time step dt_est (free body 6x5x4, horizon 3.015 h):
//     finite and positive; against the true limit dt_true = 2 / sqrt(
//     lambda_max) of velocity-Verlet with lumped mass, lambda_max of -rho^-1
//     dF/du by 60 Lanczos steps in the mass inner product on central
//     differences of the force: dt_est / dt_true in (0.1, 1 + 1e-9] (the Ritz
//     value approaches lambda_max from below, so a ratio above 1 proves the
//     estimate unsafe; below 0.1 it wastes steps), settled to 1e-3 over the
//     last half of the steps. Velocity-Verlet from u = 0 with a random
//     velocity of 1e-3 of sqrt(K/rho): with dt = 0.95 dt_est, for 2000 steps,
//     the energy E (kinetic + sum V W) stays below E0 / (1 - 0.95^2) = 10.26
//     E0: a stable linear mode with theta = omega dt < 2 conserves v^2 +
//     (1 - theta^2/4) omega^2 x^2, so its energy stays below 1/(1 - theta^2/4)
//     of its initial (kinetic) one, and theta <= 0.95 x 2 when dt_est <=
//     dt_true. If the measured dt_true makes 3 dt_est at least 1.1 dt_true,
//     a run at 3 dt_est must exceed 10 E0 within 2000 steps (the top mode
//     grows by a factor of at least 2.4 per step).
// (g) every model must declare Bulk modulus, Shear modulus, Young's modulus
//     and Poisson's ratio (elastic_constants.h; FAIL otherwise): given the E
//     and nu of the K, G it got above, it has the same K and G within 1e-12.
// (h) thermal strain: every model must declare Thermal expansion coefficient
//     (FAIL otherwise). With alpha = 1e-4 and a uniform dT = 5 (the rigid
//     box of (a)), u = alpha dT (X - X0) is a free thermal expansion: max
//     |f| / f_ref and max |W| / (K 1e-6) below 1e-10 at every point, surface
//     included (e = |y| - |xi| - alpha dT |xi| is round-off of ~1e-16 |xi|
//     against a strain of 5e-4). The same u without the temperature is
//     printed: the force it gives (O(1) at the surface) is what the thermal
//     term must cancel. Then (d) again with alpha = 1e-4 and a nonuniform dT
//     = 3 + 2x - y + z^2 (the thermal term in the tangent).
// (f) the printed numbers (6 digits) are compared by numdiff, for 1 and 2
//     ranks, against the one stored tests/models/NAME.output; round-off
//     quantities print only their bound.

#include <perideal/solver/tangent.h>

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/lac/trilinos_vector.h>

#include <boost/property_tree/json_parser.hpp>
#include <boost/property_tree/ptree.hpp>

#include <set>

#include "../physics/harness.h"

using namespace pdtest;

namespace
{
  using Registry = perideal::Registry<perideal::Material>;

  // The elastic constants every model gets, where it declares their keys:
  // nu = 0.31, away from 1/4 where LPS's dilatation term vanishes (3K = 5G).
  constexpr double rho = 1.3, K = 2.5, G = 1.1;

  std::string
  exact(const double v)
  {
    std::ostringstream o;
    o << std::setprecision(16) << v;
    return o.str();
  }

  /// The elastic keys the suite knows and the value each gets.
  const std::map<std::string, std::string> &
  elastic_keys()
  {
    static const std::map<std::string, std::string> keys = {
      {"Density", exact(rho)},
      {"Bulk modulus", exact(K)},
      {"Shear modulus", exact(G)},
      {"Young's modulus", exact(9 * K * G / (3 * K + G))},
      {"Poisson's ratio", exact((3 * K - 2 * G) / (2 * (3 * K + G)))},
      // Plasticity: a yield stress far above every check's stresses (<~0.1),
      // so the defaults variant is the elastic model.
      {"Yield stress", "1000"}};
    return keys;
  }

  /// Density and the fewest elastic keys the model declares and accepts:
  /// K alone (bond based), K and G, or E and nu; if none works, every elastic
  /// key it declares (the variant then FAILS with the model's message).
  std::map<std::string, std::string>
  elastic_choice(const std::string &model, const std::set<std::string> &declared)
  {
    const Registry::Entry &entry = Registry::instance().get(model, "models_conformance");
    const std::vector<std::vector<std::string>> candidates = {
      {"Bulk modulus"}, {"Bulk modulus", "Shear modulus"}, {"Young's modulus", "Poisson's ratio"}};
    for (const auto &candidate : candidates)
      {
        std::map<std::string, std::string> keys;
        for (const auto &name : candidate)
          keys[name] = elastic_keys().at(name);
        // The keys besides the moduli (Density, Yield stress) that it declares.
        for (const char *other : {"Density", "Yield stress"})
          if (declared.count(other))
            keys[other] = elastic_keys().at(other);
        bool all_declared = true;
        for (const auto &[name, value] : keys)
          all_declared &= declared.count(name) > 0;
        if (!all_declared)
          continue;
        try
          {
            ParameterHandler prm;
            entry.declare(prm);
            for (const auto &[name, value] : keys)
              prm.set(name, value);
            entry.create()->parse_parameters(prm, "probe");
            return keys;
          }
        catch (const std::exception &)
          {}
      }
    std::map<std::string, std::string> keys;
    for (const auto &name : declared)
      if (elastic_keys().count(name))
        keys[name] = elastic_keys().at(name);
    return keys;
  }

  /// Options that change the force but are no Selection, with the values
  /// tried besides the default where a model declares them.
  const std::map<std::string, std::vector<std::string>> &
  known_options()
  {
    static const std::map<std::string, std::vector<std::string>> options = {
      {"Influence function", {"1 - r"}},
      // Low enough that (b)'s objectivity state (|grad u| ~ 1e-2, von Mises
      // stress ~ 0.04) yields, high enough that (c) (|H| ~ 1e-4) and (e)
      // stay elastic, where their energy checks assume it.
      {"Yield stress", {"0.005"}}};
    return options;
  }

  struct Key
  {
    std::string              name, default_value;
    std::vector<std::string> selection; // the values of a Patterns::Selection, else empty
  };

  /// The top-level keys a model declares, read from its ParameterHandler's
  /// JSON (names as declared; keys in subsections keep their defaults).
  std::vector<Key>
  declared_keys(const Registry::Entry &entry)
  {
    ParameterHandler prm;
    entry.declare(prm);
    std::stringstream json;
    prm.print_parameters(json, ParameterHandler::JSON);
    boost::property_tree::ptree tree;
    boost::property_tree::read_json(json, tree);
    std::vector<Key> keys;
    for (const auto &[name, node] : tree)
      {
        if (!node.get_child_optional("value"))
          continue;
        Key key{name, node.get<std::string>("default_value"), {}};
        const std::string pattern = node.get<std::string>("pattern_description");
        const std::string head    = "[Selection ";
        if (pattern.compare(0, head.size(), head) == 0)
          {
            std::string list = pattern.substr(head.size(), pattern.find(']') - head.size());
            list.erase(list.find_last_not_of(' ') + 1);
            std::istringstream in(list);
            for (std::string v; std::getline(in, v, '|');)
              key.selection.push_back(v);
          }
        keys.push_back(key);
      }
    return keys;
  }

  struct Variant
  {
    std::string  label;
    MaterialSpec spec;
  };

  /// The model with the elastic keys it declares and every other key at its
  /// default; then one variant per other value of each Selection key and of
  /// each known option it declares (one key changed at a time).
  std::vector<Variant>
  variants_of(const std::string &model, const std::vector<Key> &keys)
  {
    std::set<std::string> declared;
    for (const auto &key : keys)
      declared.insert(key.name);
    MaterialSpec base{model, elastic_choice(model, declared)};
    std::vector<Variant> variants = {{"defaults", base}};
    for (const auto &key : keys)
      {
        std::vector<std::string> values = key.selection;
        if (known_options().count(key.name))
          values = known_options().at(key.name);
        for (const auto &value : values)
          if (value != key.default_value)
            {
              variants.push_back({key.name + " = " + value, base});
              variants.back().spec.keys[key.name] = value;
            }
      }
    return variants;
  }

  /// A number for the comparison of 1 and 2 ranks: 6 significant digits.
  void
  info(Report &report, const std::string &name, const double v)
  {
    report.line(name + " = " + sci(v, 6));
  }

  // ---------------------------------------------------------------------
  // (a), (b): rigid motions and objectivity.
  void
  check_rigid_motions(const MPI_Comm comm, Report &report, const MaterialSpec &spec)
  {
    const double horizon = rigid_box::horizon;
    Harness      h(comm, rigid_box::lower, rigid_box::upper, rigid_box::cells, horizon, spec);
    const double k     = h.material->bulk_modulus();
    const double f_ref = k * 1e-3 / horizon, W_ref = k * 1e-6;
    report.line("  rigid motions: box of " + std::to_string(h.cloud.n_global()) + " points, " +
                sci(Utilities::MPI::sum(double(h.bonds.n_bonds()), comm), 8) + " bonds");

    const Tensor<1, 3> c = rigid_box::translation, axis = rigid_box::axis;
    Tensor<1, 3>       p;
    p[0] = 0.9, p[1] = 0.5, p[2] = -0.2; // a point of the axis, outside the box
    const Tensor<2, 3> I = unit_symmetric_tensor<3>();
    const std::vector<RigidMotion> motions = {{"(a) translation by (0.3, -0.7, 1.1)", I, c},
                                              {"(b) rotation 90 deg about an off-axis line", rotation(axis, M_PI / 2), {}},
                                              {"(b) rotation 1e-3 rad about that line", rotation(axis, 1e-3), {}}};
    const auto moved = [&](const RigidMotion &m, const Tensor<1, 3> &x) {
      return Tensor<1, 3>(m.Q * (x - p) + p + m.c);
    };
    for (const auto &m : motions)
      {
        h.set_displacement([&](const Point<3> &x) { return Tensor<1, 3>(moved(m, x) - x); });
        h.evaluate(true);
        double f_max = 0, W_max = 0;
        for (unsigned int i = 0; i < h.cloud.n_owned(); ++i)
          {
            f_max = std::max(f_max, h.force_of(i).norm());
            W_max = std::max(W_max, std::abs(h.energy[i]));
          }
        report.line("  " + m.name);
        report.below("    max |f| / (K 1e-3 / horizon)", Utilities::MPI::max(f_max, comm) / f_ref, 1e-10);
        report.below("    max |W| / (K 1e-6)", Utilities::MPI::max(W_max, comm) / W_ref, 1e-10);
      }

    // (b) objectivity: a deformed state, then the same state moved rigidly.
    const auto u0 = non_affine_displacement;
    h.set_displacement(u0);
    h.evaluate(true);
    const unsigned int        n = h.cloud.n_owned();
    std::vector<Tensor<1, 3>> f0(n);
    std::vector<double>       W0(h.energy);
    double                    f0_max = 0;
    for (unsigned int i = 0; i < n; ++i)
      f0[i] = h.force_of(i), f0_max = std::max(f0_max, f0[i].norm());
    const RigidMotion m{"", rotation(axis, M_PI / 2), c};
    h.set_displacement([&](const Point<3> &x) { return Tensor<1, 3>(moved(m, x + u0(x)) - x); });
    h.evaluate(true);
    double df = 0, dW = 0;
    for (unsigned int i = 0; i < n; ++i)
      {
        df = std::max(df, (h.force_of(i) - m.Q * f0[i]).norm());
        dW = std::max(dW, std::abs(h.energy[i] - W0[i]));
      }
    report.line("  (b) objectivity: a non-affine state y0, then Q y0 + c (90 deg, translated)");
    info(report, "    max |f0| / (K 1e-3 / horizon)", Utilities::MPI::max(f0_max, comm) / f_ref);
    report.below("    max |f1 - Q f0| / (K 1e-3 / horizon)", Utilities::MPI::max(df, comm) / f_ref, 1e-10);
    report.below("    max |W1 - W0| / (K 1e-6)", Utilities::MPI::max(dW, comm) / W_ref, 1e-10);
  }

  // ---------------------------------------------------------------------
  // (c) homogeneous deformation.
  void
  check_homogeneous(const MPI_Comm comm, Report &report, const MaterialSpec &spec)
  {
    const Point<3>     lower(0, 0, 0), upper(1, 1, 1);
    const unsigned int n       = 14;
    const double       horizon = 3.015 / n;
    Harness            h(comm, lower, upper, {{n, n, n}}, horizon, spec);
    const double       k = h.material->bulk_modulus(), g = h.material->shear_modulus();

    Tensor<2, 3>       H;
    const double       entries[3][3] = {{1.0, 0.4, -0.3}, {-0.2, -0.6, 0.5}, {0.7, 0.1, 0.8}};
    for (unsigned int a = 0; a < 3; ++a)
      for (unsigned int b = 0; b < 3; ++b)
        H[a][b] = 1e-4 * entries[a][b];
    const SymmetricTensor<2, 3> eps = symmetrize(H);
    const SymmetricTensor<2, 3> dev = deviator(eps);
    const double W_continuum        = 0.5 * k * trace(eps) * trace(eps) + g * scalar_product(dev, dev);
    const double f_ref              = k * 1e-3 / horizon;

    h.set_displacement([&](const Point<3> &x) { return Tensor<1, 3>(H * Tensor<1, 3>(x)); });
    h.evaluate(true);
    double       f_max = 0, W_all = 0, lo = 1e300, hi = -1e300, sum = 0;
    unsigned int n_deep = 0;
    for (unsigned int i = 0; i < h.cloud.n_owned(); ++i)
      {
        W_all = std::max(W_all, std::abs(h.energy[i]));
        if (h.depth(i, lower, upper) > 2 * horizon)
          {
            f_max = std::max(f_max, h.force_of(i).norm());
            const double r = h.energy[i] / W_continuum;
            lo = std::min(lo, r), hi = std::max(hi, r), sum += r;
            ++n_deep;
          }
      }
    n_deep = Utilities::MPI::sum(n_deep, comm);
    sum    = Utilities::MPI::sum(sum, comm);
    lo     = Utilities::MPI::min(lo, comm);
    hi     = Utilities::MPI::max(hi, comm);
    report.line("  (c) homogeneous u = H X, |H| ~ 1e-4 (not symmetric), cube 14^3: " + std::to_string(n_deep) +
                " points deeper than 2 horizons");
    report.below("    max |f| / (K 1e-3 / horizon) there", Utilities::MPI::max(f_max, comm) / f_ref, 1e-10);
    if (Utilities::MPI::max(W_all, comm) == 0)
      {
        report.line("    W: the model reports no strain energy density; not checked");
        return;
      }
    info(report, "    mean W / (K tr(eps)^2/2 + G dev(eps):dev(eps)) there", sum / n_deep);
    const double dev_ratio = std::max(std::abs(lo - 1), std::abs(hi - 1));
    report.check("    max |W / W_continuum - 1| there", dev_ratio, dev_ratio < 0.2, "< 0.2: the lattice's quadrature");
  }

  // ---------------------------------------------------------------------
  // (d) tangent against finite differences.
  void
  check_tangent(const MPI_Comm comm, Report &report, const MaterialSpec &spec, const bool heated = false)
  {
    const double spacing = 0.25;
    Harness      h(comm, Point<3>(0, 0, 0), Point<3>(1.5, 1, 1), {{6, 4, 4}}, 2.015 * spacing, spec);
    if (heated)
      for (unsigned int i = 0; i < h.cloud.n_local(); ++i)
        {
          const Point<3> x = h.cloud.position(i);
          h.temperature_change.push_back(3 + 2 * x[0] - x[1] + x[2] * x[2]);
        }
    h.set_random_displacement(0.05 * spacing);
    // A step of 0.3 from the initial state: a rate model's tangent includes
    // its history's response over the step (Viscoelastic: e^b follows e^d).
    h.dt = 0.3;
    h.evaluate(false);

    const std::vector<std::uint8_t> free(3 * h.cloud.n_local(), 0);
    const unsigned int              hops = h.material->coupling_hops();
    perideal::Tangent               analytic, fd;
    analytic.reinit(h.cloud, h.bonds, hops, comm);
    if (!h.material->add_tangent(h.state(false), h.points, analytic.begin(free)))
      {
        report.line("  (d) no analytic tangent: the implicit solvers use finite differences; not checked");
        return;
      }
    analytic.finish();
    fd.reinit(h.cloud, h.bonds, hops, comm);
    fd.begin(free);
    fd.add_finite_differences(h.u, h.force, [&] { h.evaluate(false); }, 1e-6 * spacing, hops * h.horizon);
    fd.finish();

    double max_a = 0, max_diff = 0;
    for (const auto row : analytic.owned)
      for (auto it = analytic.matrix.begin(row); it != analytic.matrix.end(row); ++it)
        {
          max_a    = std::max(max_a, std::abs(it->value()));
          max_diff = std::max(max_diff, std::abs(it->value() - fd.matrix.el(row, it->column())));
        }
    max_a    = Utilities::MPI::max(max_a, comm);
    max_diff = Utilities::MPI::max(max_diff, comm);
    report.line(std::string(heated ? "  (h) with alpha = 1e-4 and dT = 3 + 2x - y + z^2: (d) " : "  (d) ") +
                "tangent on a random state (5% of the spacing), box 6x4x4, coupling_hops = " + std::to_string(hops));
    report.below("    max |K - K_fd| / max |K|", max_diff / max_a, 1e-6);
    info(report, "    Frobenius norm of K", analytic.matrix.frobenius_norm());
  }

  // ---------------------------------------------------------------------
  // (e) stable time step.
  void
  check_time_step(const MPI_Comm comm, Report &report, const MaterialSpec &spec)
  {
    const double       spacing = 0.125;
    Harness            h(comm, Point<3>(0, 0, 0), Point<3>(0.75, 0.625, 0.5), {{6, 5, 4}}, 3.015 * spacing, spec);
    const double       density = h.material->density();
    const double       dt_est  = h.stable_time_step();
    const unsigned int n       = h.cloud.n_owned();
    const double      *V       = h.cloud.volume.data();
    report.line("  (e) stable time step: free body 6x5x4, horizon 3.015 h");
    info(report, "    dt_est", dt_est);
    report.check("    dt_est finite and positive", dt_est, std::isfinite(dt_est) && dt_est > 0, "> 0");
    if (!(std::isfinite(dt_est) && dt_est > 0))
      return;

    // lambda_max of -rho^-1 dF/du by Lanczos in the mass inner product.
    std::vector<double> start(3 * n);
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int c = 0; c < 3; ++c)
        start[3 * i + c] = noise(h.cloud.hash(i), 10 + c);
    const auto [lambda, settled] = largest_eigenvalue(h, start, 1e-6 * spacing);
    const double ratio  = dt_est * std::sqrt(lambda) / 2;
    info(report, "    dt_true = 2 / sqrt(lambda_max)", 2 / std::sqrt(lambda));
    report.check("    dt_est / dt_true", ratio, ratio <= 1 + 1e-9 && ratio > 0.1, "in (0.1, 1 + 1e-9]");
    report.below("    change of lambda_max over the last half of the Lanczos steps", settled, 1e-3);

    // Velocity-Verlet from u = 0 with a random velocity of 1e-3 of the wave speed.
    const auto verlet = [&](const double dt, const unsigned int steps, const double stop_above) {
      std::vector<double> u(3 * n, 0.0), vel(3 * n), a(3 * n, 0.0);
      for (unsigned int i = 0; i < n; ++i)
        for (unsigned int c = 0; c < 3; ++c)
          vel[3 * i + c] = 1e-3 * std::sqrt(K / rho) * noise(h.cloud.hash(i), 20 + c);
      const auto energy = [&] {
        double e = 0;
        for (unsigned int k = 0; k < 3 * n; ++k)
          e += 0.5 * density * V[k / 3] * vel[k] * vel[k];
        for (unsigned int i = 0; i < n; ++i)
          e += V[i] * h.energy[i];
        return Utilities::MPI::sum(e, comm);
      };
      h.set_displacement(u);
      h.evaluate(true);
      const double E0    = energy();
      double       E_max = 1;
      unsigned int step  = 0;
      while (step < steps && E_max <= stop_above)
        {
          for (unsigned int k = 0; k < 3 * n; ++k)
            {
              vel[k] += 0.5 * dt * a[k];
              u[k] += dt * vel[k];
            }
          h.set_displacement(u);
          h.evaluate(true);
          for (unsigned int k = 0; k < 3 * n; ++k)
            {
              a[k] = h.force.local_element(k) / density;
              vel[k] += 0.5 * dt * a[k];
            }
          ++step;
          E_max = std::max(E_max, energy() / E0);
        }
      return std::make_pair(E_max, step);
    };
    const double bound   = 1 / (1 - 0.95 * 0.95);
    const auto [E_max, steps] = verlet(0.95 * dt_est, 2000, bound);
    report.check("    0.95 dt_est, 2000 steps: max E / E0", E_max, E_max <= bound && steps == 2000,
                 "<= 1/(1 - 0.95^2) = " + sci(bound, 4));
    if (3 * ratio >= 1.1)
      {
        const auto [E3, steps3] = verlet(3 * dt_est, 2000, 10);
        report.check("    3 dt_est (above the true limit): steps until E > 10 E0", steps3, E3 > 10,
                     "blows up within 2000 steps");
      }
    else
      report.line("    3 dt_est is below the true limit: no blow-up to check");
  }

  // ---------------------------------------------------------------------
  // (g) any two of K, G, E, nu give the same moduli.
  void
  check_elastic_constants(Report &report, const MaterialSpec &spec, const std::set<std::string> &declared)
  {
    for (const char *key : {"Bulk modulus", "Shear modulus", "Young's modulus", "Poisson's ratio"})
      if (!declared.count(key))
        {
          report.line("  FAIL: " + spec.model + " declares no key '" + key +
                      "': every material takes any two of Bulk modulus, Shear modulus, Young's modulus, "
                      "Poisson's ratio (declare_elastic_constants(), elastic_constants.h)");
          ++report.failures;
          return;
        }
    const Registry::Entry &entry  = Registry::instance().get(spec.model, "models_conformance");
    const auto             create = [&](const std::map<std::string, std::string> &keys) {
      ParameterHandler prm;
      entry.declare(prm);
      for (const auto &[name, value] : keys)
        prm.set(name, value);
      auto material = entry.create();
      material->parse_parameters(prm, "test material");
      return material;
    };
    const auto   reference = create(spec.keys);
    const double k = reference->bulk_modulus(), g = reference->shear_modulus();
    std::map<std::string, std::string> keys = spec.keys;
    for (const char *key : {"Bulk modulus", "Shear modulus", "Young's modulus", "Poisson's ratio"})
      keys.erase(key);
    keys["Young's modulus"] = exact(9 * k * g / (3 * k + g));
    keys["Poisson's ratio"] = exact((3 * k - 2 * g) / (2 * (3 * k + g)));
    const auto   other = create(keys);
    const double error = std::max(std::abs(other->bulk_modulus() / k - 1), std::abs(other->shear_modulus() / g - 1));
    report.line("  (g) given the E and nu of its K, G");
    report.below("    max relative difference of K and G", error, 1e-12);
  }

  // ---------------------------------------------------------------------
  // (h) thermal strain: a free, uniformly heated body is stress free.
  void
  check_thermal(const MPI_Comm comm, Report &report, MaterialSpec spec, const std::set<std::string> &declared)
  {
    if (!declared.count("Thermal expansion coefficient"))
      {
        report.line("  FAIL: " + spec.model +
                    " declares no key 'Thermal expansion coefficient': every model must support thermal strain "
                    "(ModelState::thermal_strain, doc/models.md)");
        ++report.failures;
        return;
      }
    const double alpha = 1e-4, dT = 5;
    spec.keys["Thermal expansion coefficient"] = exact(alpha);
    const double horizon = rigid_box::horizon;
    Harness      h(comm, rigid_box::lower, rigid_box::upper, rigid_box::cells, horizon, spec);
    const double k     = h.material->bulk_modulus();
    const double f_ref = k * 1e-3 / horizon, W_ref = k * 1e-6;
    const Tensor<1, 3> X0 = Point<3>(0.9, 0.5, -0.2);
    h.set_displacement([&](const Point<3> &x) { return Tensor<1, 3>(alpha * dT * (x - X0)); });
    const auto maxima = [&] {
      h.evaluate(true);
      double f_max = 0, W_max = 0;
      for (unsigned int i = 0; i < h.cloud.n_owned(); ++i)
        {
          f_max = std::max(f_max, h.force_of(i).norm());
          W_max = std::max(W_max, std::abs(h.energy[i]));
        }
      return std::make_pair(Utilities::MPI::max(f_max, comm) / f_ref, Utilities::MPI::max(W_max, comm) / W_ref);
    };
    const auto [f_cold, W_cold] = maxima();
    h.temperature_change.assign(h.cloud.n_local(), dT);
    const auto [f_max, W_max] = maxima();
    report.line("  (h) free thermal expansion: alpha = 1e-4, uniform dT = 5, u = alpha dT (X - X0)");
    info(report, "    without the temperature: max |f| / (K 1e-3 / horizon)", f_cold);
    info(report, "    without the temperature: max W / (K 1e-6)", W_cold);
    report.below("    max |f| / (K 1e-3 / horizon)", f_max, 1e-10);
    report.below("    max |W| / (K 1e-6)", W_max, 1e-10);
    check_tangent(comm, report, spec, true);
  }

  // ---------------------------------------------------------------------
  void
  check_material(const MPI_Comm comm, Report &report, const std::string &model)
  {
    const Registry::Entry &entry = Registry::instance().get(model, "models_conformance");
    const std::vector<Key> keys  = declared_keys(entry);
    std::string            list;
    for (const auto &key : keys)
      list += (list.empty() ? "" : ", ") + key.name;
    report.line(model + ": keys " + list);
    std::set<std::string> declared;
    for (const auto &key : keys)
      declared.insert(key.name);
    for (const auto &variant : variants_of(model, keys))
      {
        std::string set;
        for (const auto &[key, value] : variant.spec.keys)
          set += (set.empty() ? "" : ", ") + key + " = " + value;
        report.line(model + " [" + variant.label + "]: " + set + "; every other key at its default");
        try
          {
            check_rigid_motions(comm, report, variant.spec);
            check_homogeneous(comm, report, variant.spec);
            check_tangent(comm, report, variant.spec);
            check_time_step(comm, report, variant.spec);
            check_elastic_constants(report, variant.spec, declared);
            check_thermal(comm, report, variant.spec, declared);
          }
        catch (const std::exception &e)
          {
            std::string defaults;
            for (const auto &key : keys)
              if (!variant.spec.keys.count(key.name))
                defaults += (defaults.empty() ? "" : ", ") + key.name;
            // deal.II's what() carries a stack trace; its message alone names the key.
            std::ostringstream message;
            if (const auto *exc = dynamic_cast<const dealii::ExceptionBase *>(&e))
              exc->print_info(message);
            else
              message << e.what();
            std::string text = message.str();
            text.erase(0, text.find_first_not_of(" \n"));
            text.erase(text.find_last_not_of(" \n") + 1);
            report.line("  FAIL: " + model + " [" + variant.label +
                        "] cannot be created or evaluated with the keys above (kept at their default: " + defaults +
                        "): " + text);
            ++report.failures;
          }
      }
  }
} // namespace

int
main(int argc, char *argv[])
{
  if (argc == 2 && std::string(argv[1]) == "--list")
    {
      for (const auto &entry : Registry::instance().all())
        std::cout << entry.first << '\n';
      return 0;
    }
  if (argc != 2)
    {
      std::cerr << "Usage: models_conformance MATERIAL | --list" << std::endl;
      return 2;
    }
  const std::string model = argv[1];
  return run_checks(argc, argv, [&](const MPI_Comm comm, Report &report) { check_material(comm, report, model); });
}
