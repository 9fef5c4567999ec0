// The kinematics shared by the correspondence materials: see
// include/perideal/material/correspondence.h for the formulas.

#include <perideal/material/correspondence.h>
#include <perideal/material/elastic_constants.h>

#include <deal.II/base/symmetric_tensor.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

namespace perideal
{
  using namespace dealii;
  using namespace correspondence;

  namespace
  {
    // The bond work's per-bond history (correspondence.h): w, g and v.
    const std::string work_name = "corr_work";
    const std::string work_force[3]        = {"corr_work_force_x", "corr_work_force_y", "corr_work_force_z"};
    const std::string work_displacement[3] = {"corr_work_displacement_x", "corr_work_displacement_y",
                                              "corr_work_displacement_z"};

    /// One evaluation's update of the bond work from the last accepted step.
    struct WorkUpdate
    {
      explicit WorkUpdate(FieldStore &fields)
        : w_N(fields.bond_old(work_name))
        , w(fields.bond(work_name))
      {
        for (unsigned int p = 0; p < 3; ++p)
          {
            g_N[p] = fields.bond_old(work_force[p]);
            v_N[p] = fields.bond_old(work_displacement[p]);
            g[p]   = fields.bond(work_force[p]);
            v[p]   = fields.bond(work_displacement[p]);
          }
      }

      /// Bond b's pair force @p g_NP1 and relative displacement @p v_NP1.
      void
      add(const std::size_t b, const double *g_NP1, const double *v_NP1) const
      {
        double dw = 0;
        for (unsigned int p = 0; p < 3; ++p)
          {
            dw += (g_N[p][b] + g_NP1[p]) * (v_NP1[p] - v_N[p][b]);
            g[p][b] = g_NP1[p];
            v[p][b] = v_NP1[p];
          }
        w[b] = w_N[b] + 0.5 * dw;
      }

      const double *w_N, *g_N[3], *v_N[3];
      double       *w, *g[3], *v[3];
    };
  } // namespace

  void
  correspondence::polar_decomposition(const double *F, double *R, double *U, double *Uinv)
  {
    SymmetricTensor<2, 3> C;
    for (unsigned int p = 0; p < 3; ++p)
      for (unsigned int q = p; q < 3; ++q)
        C[p][q] = F[p] * F[q] + F[3 + p] * F[3 + q] + F[6 + p] * F[6 + q];
    const auto eig = eigenvectors(C);
    for (unsigned int k = 0; k < 9; ++k)
      U[k] = Uinv[k] = 0;
    for (const auto &[value, v] : eig)
      {
        const double s = std::sqrt(value);
        for (unsigned int p = 0; p < 3; ++p)
          for (unsigned int q = 0; q < 3; ++q)
            {
              U[3 * p + q] += s * v[p] * v[q];
              Uinv[3 * p + q] += v[p] * v[q] / s;
            }
      }
    multiply(F, Uinv, R);
  }

  void
  CorrespondenceMaterial::declare_kinematics_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Density", "0", Patterns::Double(), "Mass density rho.");
    prm.declare_entry("Stabilization", "Hourglass", Patterns::Selection("Hourglass|Silling|None"),
                      "Control of the zero-energy modes of the correspondence force, both zero under any "
                      "affine deformation, z = y_j - y_i - F xi: Hourglass, Peridigm's hourglass force, "
                      "a bond force c (z.M / |xi|) M, M = Y/|Y|, c = 18 C K / (pi delta^4), C the Hourglass "
                      "coefficient; "
                      "Silling, Silling (2017)'s force state c z, c = 18 C K / (pi delta^5), C the Silling "
                      "coefficient (a potential force: its energy is in W); None.");
    prm.declare_entry("Hourglass coefficient", "0.02", Patterns::Double(),
                      "C >= 0 of Stabilization = Hourglass (Peridigm's examples use 0.02).");
    prm.declare_entry("Silling coefficient", "0.02", Patterns::Double(), "C >= 0 of Stabilization = Silling.");
    declare_thermal_expansion(prm);
    declare_elastic_constants(prm);
  }

  void
  CorrespondenceMaterial::parse_kinematics_parameters(ParameterHandler &prm, const std::string &path_)
  {
    path = path_;
    rho  = prm.get_double("Density");
    require_positive(rho, path + "/Density");
    const std::string stab = prm.get("Stabilization");
    stabilization          = stab == "Hourglass" ? 1 : stab == "Silling" ? 2 : 0;
    hourglass_coefficient  = prm.get_double("Hourglass coefficient");
    silling_coefficient    = prm.get_double("Silling coefficient");
    thermal_expansion      = parse_thermal_expansion(prm, path);
    AssertThrow(std::isfinite(hourglass_coefficient) && hourglass_coefficient >= 0,
                ExcMessage(path + "/Hourglass coefficient must be >= 0, not " + prm.get("Hourglass coefficient")));
    AssertThrow(std::isfinite(silling_coefficient) && silling_coefficient >= 0,
                ExcMessage(path + "/Silling coefficient must be >= 0, not " + prm.get("Silling coefficient")));
    const ElasticConstants moduli = parse_elastic_constants(prm, path);
    K                             = moduli.K;
    G                             = moduli.G;
  }

  std::vector<PointField>
  CorrespondenceMaterial::point_fields() const
  {
    std::vector<PointField> f = {{"corr_shape_inverse", FieldUse::constant, 9},
                                 {"corr_gershgorin", FieldUse::constant, 1},
                                 {"corr_PKinv", FieldUse::stage, 9},
                                 {"corr_F", FieldUse::stage, 9, "Deformation gradient"},
                                 {"corr_cauchy", FieldUse::local, 9, "Cauchy stress"},
                                 {"corr_von_mises", FieldUse::stage, 1, "Von Mises stress"},
                                 {"corr_energy", FieldUse::local, 1}};
    if (stabilization != 0)
      f.push_back({"corr_live", FieldUse::stage, 1});
    return f;
  }

  void
  CorrespondenceMaterial::initialize(const ModelState &state, const std::vector<unsigned int> &points)
  {
    AssertThrow(state.bonds.family.empty(),
                ExcMessage(path + "/Model = " + model +
                           ": blocks of different horizons are not "
                           "supported (the shape tensor and the force state need one family per bond)"));
    stiffness_horizon   = horizon;
    const double *V       = state.cloud.volume.data();
    const bool    partial = !state.bonds.volume_fraction.empty();
    VectorType   &Kinv    = state.fields.get("corr_shape_inverse");
    VectorType   &a       = state.fields.get("corr_gershgorin");
    for (const unsigned int i : points)
      {
        if (state.bonds.offsets[i] == state.bonds.offsets[i + 1])
          {
            // A point without bonds moves freely: no shape tensor, no
            // stiffness (compute_forces gives it F = I and no stress).
            for (unsigned int k = 0; k < 9; ++k)
              Kinv.local_element(9 * i + k) = 0;
            a.local_element(i) = 0;
            continue;
          }
        double Ks[6] = {0, 0, 0, 0, 0, 0};
        for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
          {
            const unsigned int j  = state.bonds.neighbor[b];
            const auto         xi = state.cloud.bond_vector(i, j);
            const double       wV = (partial ? state.bonds.volume_fraction[b] : 1.0) * V[j];
            Ks[0] += wV * xi[0] * xi[0], Ks[1] += wV * xi[1] * xi[1], Ks[2] += wV * xi[2] * xi[2];
            Ks[3] += wV * xi[0] * xi[1], Ks[4] += wV * xi[1] * xi[2], Ks[5] += wV * xi[0] * xi[2];
          }
        double inverse[9];
        if (!invert_shape(Ks, inverse))
          {
            const Point<dim>   x = state.cloud.position(i);
            std::ostringstream message;
            message << path << "/Model = " << model << ": the shape tensor K = sum_j xi (x) xi V_j of "
                    << "the point at (" << x[0] << ", " << x[1] << ", " << x[2] << ") of block " << block
                    << " is singular or badly conditioned (det K / (tr K / 3)^3 < " << degenerate_ratio
                    << "): its family of " << state.bonds.offsets[i + 1] - state.bonds.offsets[i]
                    << " bonds does not span space (too few neighbors, or all in a plane or on a line); "
                       "enlarge the horizon or refine the discretization";
            AssertThrow(false, ExcMessage(message.str()));
          }
        for (unsigned int k = 0; k < 9; ++k)
          Kinv.local_element(9 * i + k) = inverse[k];
        // a_i = sum_j w |K_i^-1 xi| V_j: the row sum of |dF_i/du_j| (stable_time_step()).
        double ai = 0;
        for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
          {
            const unsigned int j  = state.bonds.neighbor[b];
            const auto         xi = state.cloud.bond_vector(i, j);
            const double       wV = (partial ? state.bonds.volume_fraction[b] : 1.0) * V[j];
            double             g2 = 0;
            for (unsigned int p = 0; p < 3; ++p)
              {
                const double g = inverse[3 * p] * xi[0] + inverse[3 * p + 1] * xi[1] + inverse[3 * p + 2] * xi[2];
                g2 += g * g;
              }
            ai += wV * std::sqrt(g2);
          }
        a.local_element(i) = ai;
      }
  }

  void
  CorrespondenceMaterial::compute_force(const ModelState &state, const std::vector<unsigned int> &points) const
  {
    if (state.damage)
      force_variants<BondDamage::continuous>(state, points);
    else if (state.broken)
      force_variants<BondDamage::read>(state, points);
    else
      force_variants<BondDamage::none>(state, points);
  }

  double
  CorrespondenceMaterial::stable_time_step(const ModelState &state, const std::vector<unsigned int> &points) const
  {
    // Gershgorin bound in 3x3 blocks (spectral norms, an operator norm of
    // the block matrix, so it bounds the spectral radius) of the force
    // linearized at the reference state, g_ij = K_i^-1 xi,
    // a_i = sum_j w |g_ij| V_j (the sum of |dF_i/du_l| over l is <= 2 a_i),
    // |C| = max(3K, 2G) the norm of the isotropic elasticity tensor:
    //   rho lambda_i <= 2 |C| (a_i^2 + sum_j w |K_j^-1 xi| V_j a_j)      (P_i, P_j)
    //                 + sum_j s V_j (4 + 2 |xi| (a_i + a_j))               (stabilization)
    // with s = c w (Silling) or c w / |xi| (Hourglass), from
    // f_i = sum_j s V_j (2 Y - F_i xi - F_j xi) (Hourglass: its projection on M).
    // An inelastic law only softens the response: the elastic bound holds.
    const double *V       = state.cloud.volume.data();
    const double *Kinv    = state.fields.get("corr_shape_inverse").begin();
    const double *a       = state.fields.get("corr_gershgorin").begin();
    const bool    partial = !state.bonds.volume_fraction.empty();
    const double  norm_C  = std::max(3 * K, 2 * G);
    const double  c       = stabilization_constant();
    double        dt      = std::numeric_limits<double>::max();
    for (const unsigned int i : points)
      {
        double corr = a[i] * a[i], stab = 0;
        for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
          {
            const unsigned int j  = state.bonds.neighbor[b];
            const auto         xi = state.cloud.bond_vector(i, j);
            const double       wV = (partial ? state.bonds.volume_fraction[b] : 1.0) * V[j];
            const double       r0 = xi.norm();
            double             g2 = 0;
            for (unsigned int p = 0; p < 3; ++p)
              {
                const double g = Kinv[9 * j + 3 * p] * xi[0] + Kinv[9 * j + 3 * p + 1] * xi[1] +
                                 Kinv[9 * j + 3 * p + 2] * xi[2];
                g2 += g * g;
              }
            corr += wV * std::sqrt(g2) * a[j];
            stab += (stabilization == 2 ? c : c / r0) * wV * (4 + 2 * r0 * (a[i] + a[j]));
          }
        const double lambda = (2 * norm_C * corr + stab) / rho;
        if (lambda > 0)
          dt = std::min(dt, 2 / std::sqrt(lambda));
      }
    return dt;
  }

  double
  CorrespondenceMaterial::stabilization_constant() const
  {
    const double d4 = std::pow(stiffness_horizon, 4);
    if (stabilization == 1)
      return 18 * hourglass_coefficient * K / (M_PI * d4);
    if (stabilization == 2)
      return 18 * silling_coefficient * K / (M_PI * d4 * stiffness_horizon);
    return 0;
  }

  void
  CorrespondenceMaterial::bond_energies(const ModelState &state, const unsigned int i, double *w) const
  {
    const double *latest = state.fields.bond_latest(work_name);
    std::copy(latest + state.bonds.offsets[i], latest + state.bonds.offsets[i + 1], w);
  }

  std::vector<BondField>
  CorrespondenceMaterial::bond_fields() const
  {
    if (!work)
      return {};
    std::vector<BondField> f = {{work_name, true}};
    for (unsigned int p = 0; p < 3; ++p)
      {
        f.push_back({work_force[p], true});
        f.push_back({work_displacement[p], true});
      }
    return f;
  }

  template <BondDamage mode>
  void
  CorrespondenceMaterial::force_variants(const ModelState &state, const std::vector<unsigned int> &points) const
  {
    with_flag(state.energy != nullptr, [&](auto energy) {
      with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
        with_flag(work, [&](auto track) {
          constexpr bool E = decltype(energy)::value, P = decltype(periodic)::value, T = decltype(track)::value;
          if (stabilization == 1)
            force<mode, E, P, 1, T>(state, points);
          else if (stabilization == 2)
            force<mode, E, P, 2, T>(state, points);
          else
            force<mode, E, P, 0, T>(state, points);
        });
      });
    });
  }

  template <BondDamage mode, bool energy, bool periodic, int stab, bool track>
  void
  CorrespondenceMaterial::force(const ModelState &state, const std::vector<unsigned int> &points) const
  {
    const Family  fam(state);
    const double *PK   = state.fields.get("corr_PKinv").begin();
    const double *Fs   = state.fields.get("corr_F").begin();
    const double *Wf   = state.fields.get("corr_energy").begin();
    const double *live = stab != 0 ? state.fields.get("corr_live").begin() : nullptr;
    const double  c    = stabilization_constant();
    double       *f    = state.force;
    std::optional<WorkUpdate> work_update;
    if constexpr (track)
      work_update.emplace(state.fields);
    for (const unsigned int i : points)
      {
        const BondOrigin origin(fam.X, fam.u, i);
        const double    *PKi = PK + 9 * i, *Fi = Fs + 9 * i;
        const double     li  = stab != 0 ? live[i] : 0.0;
        double           fx = 0, fy = 0, fz = 0, Ws = 0;
        for (std::size_t b = fam.offsets[i]; b < fam.offsets[i + 1]; ++b)
          {
            const unsigned int j = fam.neighbor[b];
            double             e[3], y[3];
            bond_vectors<periodic>(fam.X, fam.u, j, origin, fam.box, e, y);
            const double  wV  = fam.weight<mode>(b) * fam.V[j];
            const double *PKj = PK + 9 * j;
            // Tracking the work, t is first the pair force per unit volume
            // of each end without beta (1 * x is exact, so the forces of
            // the other variants keep their round-off), then scaled by wV.
            const double scale = track ? 1.0 : wV;
            double       t[3];
            for (unsigned int p = 0; p < 3; ++p)
              t[p] = scale * ((PKi[3 * p] + PKj[3 * p]) * e[0] + (PKi[3 * p + 1] + PKj[3 * p + 1]) * e[1] +
                              (PKi[3 * p + 2] + PKj[3 * p + 2]) * e[2]);
            if (stab != 0)
              {
                const double *Fj = Fs + 9 * j;
                const double  lj = live[j];
                double        zi[3], zj[3];
                for (unsigned int p = 0; p < 3; ++p)
                  {
                    zi[p] = li * (y[p] - (Fi[3 * p] * e[0] + Fi[3 * p + 1] * e[1] + Fi[3 * p + 2] * e[2]));
                    zj[p] = lj * (y[p] - (Fj[3 * p] * e[0] + Fj[3 * p + 1] * e[1] + Fj[3 * p + 2] * e[2]));
                  }
                if (stab == 2)
                  {
                    for (unsigned int p = 0; p < 3; ++p)
                      t[p] += c * scale * (zi[p] + zj[p]);
                    if (energy)
                      Ws += wV * (zi[0] * zi[0] + zi[1] * zi[1] + zi[2] * zi[2]);
                  }
                else
                  {
                    const double r0 = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
                    const double r2 = y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
                    const double k  = c * scale *
                                     ((zi[0] + zj[0]) * y[0] + (zi[1] + zj[1]) * y[1] + (zi[2] + zj[2]) * y[2]) /
                                     (r0 * r2);
                    for (unsigned int p = 0; p < 3; ++p)
                      t[p] += k * y[p];
                  }
              }
            if constexpr (track)
              {
                const double intact = fam.intact<mode>(b);
                double       g[3], v[3];
                for (unsigned int p = 0; p < 3; ++p)
                  {
                    g[p] = intact * t[p];
                    v[p] = y[p] - e[p];
                    t[p] *= wV;
                  }
                work_update->add(b, g, v);
              }
            fx += t[0];
            fy += t[1];
            fz += t[2];
          }
        f[3 * i] += fx;
        f[3 * i + 1] += fy;
        f[3 * i + 2] += fz;
        if (energy)
          state.energy[i] += Wf[i] + 0.5 * c * Ws;
      }
  }
} // namespace perideal
