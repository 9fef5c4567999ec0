#pragma once
// A test harness that builds the pieces of a run by hand (box scene, points,
// nonlocal ghosts, bonds, one material) so that a test can set any
// displacement field and read the force density, dilatation and energy
// density of every owned point. It evaluates the material the way the core
// does: initialize, ghost the constant fields, compute_stage, ghost the stage
// fields, compute_force. With a second block (SecondBlock: the points with x
// beyond a plane, their own horizon and a second instance of the material)
// the blocks' horizons differ and the bonds carry Bonds::family. Its Report
// prints the lines of the suite's checker library (tests/tools/check.h) on
// rank 0.

#include "../tools/check.h"

#include <perideal/base/input.h>
#include <perideal/discretization/point_cloud.h>
#include <perideal/geometry/scene.h>
#include <perideal/material/material.h>
#include <perideal/neighborhood/bonds.h>
#include <perideal/neighborhood/partial_volumes.h>

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/tensor.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_dgq.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/physics/transformations.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace pdtest
{
  using namespace dealii;

  /// A value in [-1, 1) from a point's rank-independent hash and a salt:
  /// perturbed states that are the same on any number of ranks.
  inline double
  noise(const std::uint64_t hash, const unsigned int salt)
  {
    std::uint64_t x = hash ^ (0x9e3779b97f4a7c15ULL * (salt + 1));
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdULL;
    x ^= x >> 33;
    return double(x >> 11) / double(1ULL << 52) - 1;
  }
  using perideal::dim;

  struct MaterialSpec
  {
    std::string                        model;
    std::map<std::string, std::string> keys; // e.g. {"Bulk modulus", "1"}
    /// Material::request_bond_energy() before the fields are declared, as
    /// the core does for a block under Critical energy.
    bool bond_energy = false;
  };

  /// The points with x > @p from_x form block 1, with horizon @p horizon.
  struct SecondBlock
  {
    double from_x  = std::numeric_limits<double>::infinity();
    double horizon = 0;
  };

  /// A variant of a bond-energy test: a material and the scene's switches.
  struct EnergyVariant
  {
    std::string  name;
    MaterialSpec spec;
    bool         partial  = false;
    bool         periodic = false;
    bool         heated   = false;
    SecondBlock  second   = {};
  };

  /// Every variant of PMB and LPS that enters a bond's energy (influence
  /// function, surface correction, partial volumes, periodic, temperature,
  /// two horizons) on a lattice of @p n cells per unit length, for the tests
  /// of the energies (bond_energy.cc, released_energy.cc).
  inline std::vector<EnergyVariant>
  energy_variants(const unsigned int n)
  {
    const MaterialSpec pmb{"PMB", {{"Density", "1"}, {"Bulk modulus", "1"}, {"Thermal expansion coefficient", "0.01"}}};
    const MaterialSpec lps{"LPS",
                           {{"Density", "1"},
                            {"Bulk modulus", "1"},
                            {"Shear modulus", "0.35"},
                            {"Thermal expansion coefficient", "0.01"}}};
    std::vector<EnergyVariant> variants = {{"PMB", pmb}, {"LPS, omega = 1", lps}};
    variants.push_back({"LPS, omega = 1 - r", lps});
    variants.back().spec.keys["Influence function"] = "1 - r";
    variants.push_back({"PMB, surface correction", pmb});
    variants.back().spec.keys["Surface correction"] = "Energy";
    variants.push_back({"LPS, surface correction", lps});
    variants.back().spec.keys["Surface correction"] = "Energy";
    variants.push_back({"PMB, partial volumes", pmb, true});
    variants.push_back({"LPS, partial volumes", lps, true});
    variants.push_back({"PMB, periodic", pmb, false, true});
    variants.push_back({"LPS, periodic", lps, false, true});
    variants.push_back({"PMB, temperature", pmb, false, false, true});
    variants.push_back({"LPS, temperature", lps, false, false, true});
    variants.push_back({"PMB, two horizons", pmb, false, false, false, {0.5, 2.015 / n}});
    variants.push_back({"LPS, two horizons", lps, false, false, false, {0.5, 2.015 / n}});
    return variants;
  }

  class Harness
  {
  public:
    Harness(const MPI_Comm                     comm,
            const Point<3>                    &lower,
            const Point<3>                    &upper,
            const std::array<unsigned int, 3> &subdivisions,
            const double                       horizon,
            const MaterialSpec                &spec,
            const std::function<double(const Point<3> &)> &energy_weight = {},
            const bool                                     partial_volumes = false,
            const std::array<bool, 3>                     &periodic        = {{false, false, false}},
            const SecondBlock                             &second          = {})
      : comm(comm)
      , horizon(horizon)
      , triangulation(comm)
      , fe(FE_DGQ<3>(0), 3)
      , dof_handler(triangulation)
    {
      // The box scene as a parameter file would give it (17 digits: exact).
      perideal::Scene scene;
      {
        ParameterHandler prm;
        perideal::Scene::declare_parameters(prm);
        const auto number = [](const double x) {
          std::ostringstream s;
          s << std::setprecision(17) << x;
          return s.str();
        };
        const auto triple = [&](const auto &v) { return number(v[0]) + "," + number(v[1]) + "," + number(v[2]); };
        std::string directions;
        for (unsigned int d = 0; d < 3; ++d)
          if (periodic[d])
            directions += (directions.empty() ? "" : ",") + std::string(1, char('x' + d));
        prm.set("Type", "Box");
        prm.set("Horizon", number(horizon));
        prm.set("Periodic directions", directions);
        prm.enter_subsection("Box");
        prm.set("Lower corner", triple(lower));
        prm.set("Upper corner", triple(upper));
        prm.set("Subdivisions", triple(subdivisions));
        prm.leave_subsection();
        scene.parse_parameters(prm);
      }
      scene.create_triangulation(triangulation);
      dof_handler.distribute_dofs(fe);
      cloud.periodicity = scene.periodicity(triangulation);

      const bool                two_blocks = second.horizon > 0;
      const std::vector<double> horizons   = two_blocks ? std::vector<double>{horizon, second.horizon} :
                                                          std::vector<double>{horizon};
      cloud.build(dof_handler,
                  [&](const perideal::CellIterator &cell) { return cell->center()[0] > second.from_x ? 1 : 0; },
                  std::max(horizon, second.horizon), comm, {}, partial_volumes);
      bonds = perideal::find_families(cloud, horizons, comm, cloud.max_cell_radius);
      if (partial_volumes)
        perideal::compute_partial_volumes(cloud, bonds, horizons);
      fields = std::make_unique<perideal::FieldStore>(cloud);
      u.reinit(cloud.vector_partitioner);
      force.reinit(cloud.vector_partitioner);
      energy.assign(cloud.n_owned(), 0.0);
      points.resize(cloud.n_owned());
      std::iota(points.begin(), points.end(), 0u);
      block_points.resize(horizons.size());
      for (const unsigned int i : points)
        block_points[cloud.block[i]].push_back(i);

      for (unsigned int b = 0; b < horizons.size(); ++b)
        {
          ParameterHandler prm;
          const auto &entry = perideal::Registry<perideal::Material>::instance().get(spec.model, "test");
          entry.declare(prm);
          for (const auto &[key, value] : spec.keys)
            prm.set(key, value);
          materials.push_back(entry.create());
          materials.back()->parse_parameters(prm, "test material");
          materials.back()->set_block(b, horizons[b]);
          if (spec.bond_energy)
            materials.back()->request_bond_energy();
          for (const auto &f : materials.back()->point_fields())
            fields->declare(f);
          for (const auto &f : materials.back()->bond_fields())
            fields->declare(f, bonds.n_bonds());
          materials.back()->initialize(state(false), block_points[b]);
        }
      material = materials[0].get();
      if (energy_weight)
        {
          std::vector<double> w(cloud.n_local(), 0.0);
          for (const unsigned int i : points)
            w[i] = energy_weight(cloud.position(i));
          if (!material->weight_energy(state(false), points, w.data()))
            throw std::runtime_error(spec.model + " cannot weight its energy");
        }
      fields->update_ghost_values(perideal::FieldUse::constant);
    }

    perideal::ModelState
    state(const bool with_energy)
    {
      perideal::ModelState s{cloud,
                             bonds,
                             nullptr,
                             u.begin(),
                             force.begin(),
                             with_energy ? energy.data() : nullptr,
                             *fields};
      // As the core does: alpha of each point's material times its dT.
      thermal_strain.assign(temperature_change.size(), 0.0);
      for (unsigned int i = 0; i < temperature_change.size(); ++i)
        thermal_strain[i] = materials[cloud.block[i]]->thermal_expansion_coefficient() * temperature_change[i];
      s.damage         = damage.empty() ? nullptr : damage.data();
      s.thermal_strain = temperature_change.empty() ? nullptr : thermal_strain.data();
      s.time               = time;
      s.dt                 = dt;
      return s;
    }

    /// Sets u on the owned points from @p g(reference position), then the ghosts.
    void
    set_displacement(const std::function<Tensor<1, 3>(const Point<3> &)> &g)
    {
      for (unsigned int i = 0; i < cloud.n_owned(); ++i)
        {
          const Tensor<1, 3> d = g(cloud.position(i));
          for (unsigned int c = 0; c < 3; ++c)
            u.local_element(3 * i + c) = d[c];
        }
      u.update_ghost_values();
    }

    /// u = @p amplitude noise(hash, component): a perturbed state that is the
    /// same on any number of ranks.
    void
    set_random_displacement(const double amplitude)
    {
      std::vector<double> owned(3 * cloud.n_owned());
      for (unsigned int i = 0; i < cloud.n_owned(); ++i)
        for (unsigned int c = 0; c < 3; ++c)
          owned[3 * i + c] = amplitude * noise(cloud.hash(i), c);
      set_displacement(owned);
    }

    /// Sets u on the owned points from a flat owned array, then the ghosts.
    void
    set_displacement(const std::vector<double> &owned)
    {
      for (unsigned int k = 0; k < 3 * cloud.n_owned(); ++k)
        u.local_element(k) = owned[k];
      u.update_ghost_values();
    }

    /// Force density (and energy density) of every owned point for the current u.
    void
    evaluate(const bool with_energy = true)
    {
      std::fill(force.begin(), force.begin() + 3 * cloud.n_owned(), 0.0);
      std::fill(energy.begin(), energy.end(), 0.0);
      const auto s = state(with_energy);
      for (unsigned int b = 0; b < materials.size(); ++b)
        materials[b]->compute_stage(s, block_points[b]);
      fields->update_ghost_values(perideal::FieldUse::stage);
      for (unsigned int b = 0; b < materials.size(); ++b)
        materials[b]->compute_force(s, block_points[b]);
    }

    /// The analytic tangent of every block into @p rows; false if a
    /// material has none.
    bool
    add_tangent(perideal::TangentRows &rows)
    {
      bool has = true;
      for (unsigned int b = 0; b < materials.size(); ++b)
        has &= materials[b]->add_tangent(state(false), block_points[b], rows);
      return has;
    }

    Tensor<1, 3>
    force_of(const unsigned int i) const
    {
      Tensor<1, 3> f;
      for (unsigned int c = 0; c < 3; ++c)
        f[c] = force.local_element(3 * i + c);
      return f;
    }

    double
    field(const std::string &name, const unsigned int i)
    {
      return fields->get(name).local_element(i);
    }

    /// Distance of owned point @p i to the surface of the box.
    double
    depth(const unsigned int i, const Point<3> &lower, const Point<3> &upper) const
    {
      const Point<3> x = cloud.position(i);
      double         d = std::numeric_limits<double>::max();
      for (unsigned int c = 0; c < 3; ++c)
        d = std::min({d, x[c] - lower[c], upper[c] - x[c]});
      return d;
    }

    double
    stable_time_step()
    {
      double dt = std::numeric_limits<double>::max();
      for (unsigned int b = 0; b < materials.size(); ++b)
        dt = std::min(dt, materials[b]->stable_time_step(state(false), block_points[b]));
      return Utilities::MPI::min(dt, comm);
    }

    MPI_Comm                                          comm;
    double                                            horizon;
    parallel::distributed::Triangulation<3>           triangulation;
    FESystem<3>                                       fe;
    DoFHandler<3>                                     dof_handler;
    perideal::PointCloud                              cloud;
    perideal::Bonds                                   bonds;
    std::unique_ptr<perideal::FieldStore>             fields;
    std::vector<std::unique_ptr<perideal::Material>>  materials; // by block
    perideal::Material                               *material; // block 0's
    std::vector<double> temperature_change; // T - T_ref per local point; empty: none
    std::vector<double> thermal_strain;     // state()'s alpha dT
    std::vector<std::vector<unsigned int>>            block_points;
    perideal::VectorType                              u, force;
    std::vector<double>                               energy;
    std::vector<double>                               damage; // continuous bond damage, or empty: none
    double time = 0, dt = 0; // ModelState::time and dt of the evaluations (rate models)
    std::vector<unsigned int>                         points;
  };

  /// The scene of the rigid-motion checks (physics/rigid_motion.cc,
  /// models/conformance.cc): a box off the origin with a different spacing
  /// along each axis, so that rotations move points by O(1).
  namespace rigid_box
  {
    inline const Point<3>                    lower(0.2, -0.1, 0.3), upper(1.2, 0.7, 0.9);
    inline const std::array<unsigned int, 3> cells{{8, 7, 5}}; // spacings 0.125, 0.114, 0.12
    constexpr double                         horizon = 3.015 * 0.125;
    // The translation and the rotation axis of the checks: no symmetry of the box.
    inline const Tensor<1, 3> translation = Point<3>(0.3, -0.7, 1.1), axis = Point<3>(1, -2, 3);
  } // namespace rigid_box

  /// A rigid motion y = Q x + c (about a point p: y = Q (x - p) + p + c).
  struct RigidMotion
  {
    std::string  name;
    Tensor<2, 3> Q;
    Tensor<1, 3> c;
  };

  /// The rotation by @p angle about @p axis (of any length).
  inline Tensor<2, 3>
  rotation(const Tensor<1, 3> &axis, const double angle)
  {
    return Physics::Transformations::Rotations::rotation_matrix_3d(axis / axis.norm(), angle);
  }

  /// The deformed state y0 = x + u0 of the objectivity checks: non-affine,
  /// |grad u0| ~ 1e-2.
  inline Tensor<1, 3>
  non_affine_displacement(const Point<3> &x)
  {
    Tensor<1, 3> d;
    d[0] = 1e-3 * std::sin(7 * x[1]) + 2e-3 * x[0] * x[2];
    d[1] = -1e-3 * std::cos(5 * x[0] + x[2]);
    d[2] = 1.5e-3 * x[1] * x[1];
    return d;
  }

  /// The largest eigenvalue of -rho^-1 dF/du (lumped mass; dt_true = 2 /
  /// sqrt(lambda_max) is velocity-Verlet's limit) and how far it has settled.
  struct LargestEigenvalue
  {
    double lambda;  // the largest Ritz value: approaches lambda_max from below
    double settled; // its relative change over the last half of the steps
  };

  /// Lanczos in the mass inner product (the operator is self-adjoint in it)
  /// with full reorthogonalization, @p iterations steps at most, from @p v
  /// (dim entries per owned point), on central differences of @p h's force
  /// about u = 0 with amplitude @p eps.
  inline LargestEigenvalue
  largest_eigenvalue(Harness &h, std::vector<double> v, const double eps, const unsigned int iterations = 60)
  {
    const MPI_Comm      comm    = h.comm;
    const unsigned int  n       = h.cloud.n_owned();
    const double        density = h.material->density();
    const double       *V       = h.cloud.volume.data();
    const auto          mass_dot = [&](const std::vector<double> &a, const std::vector<double> &b) {
      double s = 0;
      for (unsigned int k = 0; k < 3 * n; ++k)
        s += density * V[k / 3] * a[k] * b[k];
      return Utilities::MPI::sum(s, comm);
    };
    std::vector<double> w(3 * n), plus(3 * n);
    // y = -(1/rho) dF/du x.
    const auto apply = [&](const std::vector<double> &x, std::vector<double> &y) {
      double x_max = 0;
      for (const double e : x)
        x_max = std::max(x_max, std::abs(e));
      const double scale = eps / Utilities::MPI::max(x_max, comm);
      for (const double sign : {1.0, -1.0})
        {
          for (unsigned int k = 0; k < 3 * n; ++k)
            w[k] = sign * scale * x[k];
          h.set_displacement(w);
          h.evaluate(false);
          for (unsigned int k = 0; k < 3 * n; ++k)
            if (sign > 0)
              plus[k] = h.force.local_element(k);
            else
              y[k] = -(plus[k] - h.force.local_element(k)) / (2 * scale * density);
        }
    };
    std::vector<std::vector<double>> Q;
    std::vector<double>              alpha, beta, Av(3 * n);
    const double                     v_norm = std::sqrt(mass_dot(v, v));
    for (auto &e : v)
      e /= v_norm;
    for (unsigned int j = 0; j < iterations; ++j)
      {
        Q.push_back(v);
        apply(v, Av);
        alpha.push_back(mass_dot(Av, v));
        for (unsigned int pass = 0; pass < 2; ++pass)
          for (const auto &q : Q)
            {
              const double c = mass_dot(Av, q);
              for (unsigned int k = 0; k < 3 * n; ++k)
                Av[k] -= c * q[k];
            }
        const double b = std::sqrt(mass_dot(Av, Av));
        if (b < 1e-12 * std::abs(alpha.back()) || Q.size() == 3 * h.cloud.n_global())
          break; // an invariant subspace: its Ritz values are eigenvalues
        beta.push_back(b);
        for (unsigned int k = 0; k < 3 * n; ++k)
          v[k] = Av[k] / b;
      }
    const auto top_ritz = [&](const unsigned int m) {
      LAPACKFullMatrix<double> T(m, m);
      for (unsigned int j = 0; j < m; ++j)
        {
          T(j, j) = alpha[j];
          if (j + 1 < m)
            T(j, j + 1) = T(j + 1, j) = beta[j];
        }
      T.compute_eigenvalues();
      double top = 0;
      for (unsigned int j = 0; j < m; ++j)
        top = std::max(top, T.eigenvalue(j).real());
      return top;
    };
    const double lambda = top_ritz(alpha.size());
    return {lambda, std::abs(lambda - top_ritz((alpha.size() + 1) / 2)) / lambda};
  }

  /// The models of the coupling tests: PMB (K = 1) and LPS (K = 1, G = 0.35;
  /// not 0.6, where 3K - 5G = 0 would hide its dilatation term) with
  /// omega = 1 - r, and, if asked, LPS with omega = 1. G_continuum is the
  /// shear modulus of the continuum model of the same material (PMB: nu = 1/4).
  struct TestModel
  {
    std::string  name;
    MaterialSpec spec;
    double       G_continuum;
  };
  /// The bar of the coupling tests (blending_ghost_forces, coupled_patch):
  /// [0,3] x [0,1.5] x [0,1.5], h = 1/8, horizon 3.015 h.
  namespace coupling_bar
  {
    inline const Point<3>   lower(0, 0, 0), upper(3, 1.5, 1.5);
    constexpr unsigned int  n       = 8;
    constexpr double        h       = 1.0 / n;
    constexpr double        horizon = 3.015 * h;
  } // namespace coupling_bar

  inline std::vector<TestModel>
  coupling_models(const bool with_constant_influence)
  {
    std::vector<TestModel> models = {{"PMB", {"PMB", {{"Density", "1"}, {"Bulk modulus", "1"}}}, 0.6}};
    const MaterialSpec lps{"LPS", {{"Density", "1"}, {"Bulk modulus", "1"}, {"Shear modulus", "0.35"}}};
    if (with_constant_influence)
      models.push_back({"LPS, omega = 1", lps, 0.35});
    models.push_back({"LPS, omega = 1 - r", lps, 0.35});
    models.back().spec.keys["Influence function"] = "1 - r";
    return models;
  }

  /// A homogeneous strain of size 1e-3: uniaxial with lateral contraction
  /// plus a shear.
  inline Tensor<2, 3>
  test_strain()
  {
    Tensor<2, 3> H;
    H[0][0] = 1e-3, H[1][1] = -0.3e-3, H[2][2] = -0.3e-3, H[0][1] = H[1][0] = 0.4e-3;
    return H;
  }

  /// A deal.II vector Function<3> from a function of the position.
  inline FunctionFromFunctionObjects<3>
  vector_function(const std::function<Tensor<1, 3>(const Point<3> &)> &g)
  {
    std::vector<std::function<double(const Point<3> &)>> components;
    for (unsigned int c = 0; c < 3; ++c)
      components.emplace_back([g, c](const Point<3> &x) { return g(x)[c]; });
    return FunctionFromFunctionObjects<3>(components);
  }

  /// @p v with 3 significant digits.
  inline std::string
  short_number(const double v)
  {
    std::ostringstream o;
    o << std::setprecision(3) << v;
    return o.str();
  }

  /// Prints on rank 0 and counts failures.
  class Report
  {
  public:
    explicit Report(const MPI_Comm comm)
      : root(Utilities::MPI::this_mpi_process(comm) == 0)
    {}

    void
    line(const std::string &text)
    {
      if (root)
        std::cout << text << std::endl;
    }

    /// "name = value (bound)": passes if @p ok.
    void
    check(const std::string &name, const double value, const bool ok, const std::string &bound)
    {
      line(check_common::check_line(name, value, ok, bound, 6));
      if (!ok)
        ++failures;
    }

    /// "name < bound PASS" if @p value < @p bound, else with the value: for
    /// round-off quantities, whose digits differ between rank counts.
    void
    below(const std::string &name, const double value, const double bound)
    {
      const bool ok = value < bound;
      line(name + " < " + short_number(bound) + (ok ? "  PASS" : " FAILED: " + short_number(value)));
      if (!ok)
        ++failures;
    }

    /// "name > bound PASS" if @p value > @p bound, else with the value: for
    /// ratios over a round-off quantity, whose digits are noise.
    void
    above(const std::string &name, const double value, const double bound)
    {
      const bool ok = value > bound;
      line(name + " > " + short_number(bound) + (ok ? "  PASS" : " FAILED: " + short_number(value)));
      if (!ok)
        ++failures;
    }

    /// A number printed for comparison only (10 significant digits).
    void
    value(const std::string &name, const double v)
    {
      std::ostringstream o;
      o << std::setprecision(10) << name << " = " << v;
      line(o.str());
    }

    int
    finish()
    {
      line(check_common::verdict(failures));
      return failures == 0 ? 0 : 1;
    }

    unsigned int failures = 0;

  private:
    bool root;
  };

  /// The family of an interior point of the cubic lattice of spacing @p h
  /// (whole cells, |xi| <= horizon (1 + 1e-9), as pd_app's search) and its
  /// weighted volume m = sum |xi|^2 V (omega = 1).
  struct Lattice
  {
    std::vector<Tensor<1, 3>> xi;
    double                    m = 0;
  };

  inline Lattice
  complete_family(const double h, const double horizon, const double V)
  {
    Lattice   L;
    const int n     = int(std::ceil(horizon / h)) + 1;
    const double r2 = std::pow(horizon * (1 + 1e-9), 2);
    for (int a = -n; a <= n; ++a)
      for (int b = -n; b <= n; ++b)
        for (int c = -n; c <= n; ++c)
          {
            Tensor<1, 3> x;
            x[0] = a * h, x[1] = b * h, x[2] = c * h;
            if ((a || b || c) && x.norm_square() <= r2)
              {
                L.xi.push_back(x);
                L.m += x.norm_square() * V;
              }
          }
    return L;
  }

  /// The main() of a check program: MPI, a Report for @p body, and the exit
  /// code (0: every check passed, 1: a check failed, 2: an exception).
  inline int
  run_checks(int argc, char *argv[], const std::function<void(const MPI_Comm, Report &)> &body)
  {
    Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
    Report                           report(MPI_COMM_WORLD);
    try
      {
        body(MPI_COMM_WORLD, report);
      }
    catch (const std::exception &e)
      {
        std::cerr << "Error: " << e.what() << std::endl;
        return 2;
      }
    return report.finish();
  }

  inline std::string
  sci(const double v, const int digits = 3)
  {
    std::ostringstream o;
    o << std::setprecision(digits) << v;
    return o.str();
  }
} // namespace pdtest
