// Elastic correspondence material (state based, non-ordinary; Peridigm's
// "Elastic Correspondence"): a classical stress law through a nonlocal
// deformation gradient (Silling et al. 2007, §18; Peridigm users' guide).
// With w = omega (1 - d) beta (omega = 1, d the bond damage, beta the partial
// volume fraction), xi = X_j - X_i, Y = y_j - y_i:
//   shape tensor          K_i = sum_j w xi (x) xi V_j
//   deformation gradient  F_i = (sum_j w Y (x) xi V_j) K_i^-1
//   force state           T_ij = w P_i K_i^-1 xi   (P: first Piola-Kirchhoff)
//   force density         f_i = sum_j (T_ij - T_ji) V_j
//                             = sum_j w (P_i K_i^-1 + P_j K_j^-1) xi V_j
// P_j K_j^-1 is a stage field, ghosted before the force pass. Under an affine
// map y = F X, F_i = F exactly at every point, surface points included.
// Stress (Strain measure), with lambda = K - 2G/3 and the elastic part
// F_e = F / (1 + alpha dT) (thermal strain alpha dT: a free, uniformly heated
// body has no stress):
//   Green-Lagrange  E = (F_e^T F_e - I)/2, S = lambda tr(E) I + 2 G E,
//                   P = F_e S / (1 + alpha dT), W = lambda tr(E)^2/2 + G E:E
//   Small strain    corotational: F_e = R U (polar decomposition),
//                   eps = U - I, sigma = R (lambda tr(eps) I + 2 G eps) R^T,
//                   P = J_e sigma F_e^-T / (1 + alpha dT),
//                   W = lambda tr(eps)^2/2 + G eps:eps
// so a rigid rotation gives no stress with either. The Cauchy stress written
// to the field corr_cauchy is P F^T / det F.
// Zero-energy modes (Stabilization), with z_ij = Y - F_i xi the bond's
// departure from the point's affine map (zero under any affine deformation):
//   Hourglass  Peridigm's hourglass force, a bond force like PMB's with
//              micromodulus c = 18 C K / (pi delta^4) on the "stretch"
//              (z.M)/|xi|, M = Y/|Y|:
//              f_i += sum_j V_j c w ((z_ij + z_ji').M / |xi|) M,
//              z_ji' = Y - F_j xi (the neighbor's half: Peridigm adds each
//              bond's force to both ends). Peridigm's code multiplies by Y
//              where this has M, a factor |Y| that makes its force depend on
//              the unit of length; here it is PMB's dimension. Not a
//              potential force: W leaves it out.
//   Silling    Silling, CMAME 322 (2017) 42-57, c = 18 C K / (pi delta^5):
//              T_s = c w z, f_i += sum_j V_j c w (z_ij + z_ji'),
//              W += c/2 sum_j w |z_ij|^2 V_j; since sum_j w z (x) xi V_j = 0
//              the force is exactly -dE/du.
// Damage: K, F and the force use w, so a broken bond carries nothing (unlike
// Peridigm, issue #87). Without damage K_i^-1 is the reference one, computed
// once; with damage K_i is summed again at every evaluation. A point whose
// damaged family leaves K_i degenerate (det K / (tr K / 3)^3 < 1e-6, e.g. all
// bonds broken) carries no stress and no stabilization. At set-up the same
// test on the intact family is an error naming the point.
// Stable time step: a Gershgorin bound of the linearized force at the
// reference state (see stable_time_step()).

#include <perideal/material/elastic_constants.h>
#include <perideal/material/material.h>

#include <deal.II/base/symmetric_tensor.h>

#include <cmath>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    /// det A / (tr A / 3)^3 of a symmetric positive semidefinite 3x3 matrix
    /// below this: the family does not span space (coplanar, too few bonds).
    constexpr double degenerate_ratio = 1e-6;

    /// Inverse of the symmetric 3x3 matrix K (xx yy zz xy yz xz) into the
    /// row-major @p inverse; false if it is degenerate.
    inline bool
    invert_shape(const double (&K)[6], double *inverse)
    {
      const double a = K[0], b = K[1], c = K[2], xy = K[3], yz = K[4], xz = K[5];
      const double c00 = b * c - yz * yz, c01 = xz * yz - xy * c, c02 = xy * yz - b * xz;
      const double c11 = a * c - xz * xz, c12 = xy * xz - a * yz, c22 = a * b - xy * xy;
      const double det   = a * c00 + xy * c01 + xz * c02;
      const double trace = (a + b + c) / 3;
      if (!(trace > 0) || !(det > degenerate_ratio * trace * trace * trace))
        return false;
      const double s = 1 / det;
      inverse[0] = c00 * s, inverse[1] = c01 * s, inverse[2] = c02 * s;
      inverse[3] = c01 * s, inverse[4] = c11 * s, inverse[5] = c12 * s;
      inverse[6] = c02 * s, inverse[7] = c12 * s, inverse[8] = c22 * s;
      return true;
    }

    /// C = A B (row-major 3x3).
    inline void
    multiply(const double *A, const double *B, double *C)
    {
      for (unsigned int p = 0; p < 3; ++p)
        for (unsigned int q = 0; q < 3; ++q)
          C[3 * p + q] = A[3 * p] * B[q] + A[3 * p + 1] * B[3 + q] + A[3 * p + 2] * B[6 + q];
    }

    inline double
    determinant(const double *A)
    {
      return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
             A[2] * (A[3] * A[7] - A[4] * A[6]);
    }
  } // namespace

  class ElasticCorrespondence : public Material
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry("Density", "0", Patterns::Double(), "Mass density rho.");
      declare_elastic_constants(prm);
      prm.declare_entry("Strain measure", "Green-Lagrange", Patterns::Selection("Green-Lagrange|Small strain"),
                        "Green-Lagrange: St. Venant-Kirchhoff, S = lambda tr(E) I + 2 G E, E = (F^T F - I)/2, "
                        "P = F S. Small strain: corotational Hooke, F = R U, eps = U - I, sigma = R (lambda "
                        "tr(eps) I + 2 G eps) R^T, P = J sigma F^-T. Both give zero stress under any rigid "
                        "rotation.");
      prm.declare_entry("Stabilization", "Hourglass", Patterns::Selection("Hourglass|Silling|None"),
                        "Control of the zero-energy modes of the correspondence force, both zero under any "
                        "affine deformation, z = y_j - y_i - F xi: Hourglass, Peridigm's hourglass force, "
                        "a bond force c (z.M / |xi|) M, M = Y/|Y|, c = 18 C K / (pi delta^4), C the Hourglass "
                        "coefficient; "
                        "Silling, Silling (2017)'s force state c z, c = 18 C K / (pi delta^5), C the Silling "
                        "coefficient (a potential force: its energy is in W); None.");
      prm.declare_entry("Hourglass coefficient", "0.02", Patterns::Double(),
                        "C >= 0 of Stabilization = Hourglass (Peridigm's examples use 0.02).");
      prm.declare_entry("Silling coefficient", "0.02", Patterns::Double(),
                        "C >= 0 of Stabilization = Silling.");
      declare_thermal_expansion(prm);
    }

    void
    parse_parameters(ParameterHandler &prm, const std::string &path_) override
    {
      path = path_;
      rho  = prm.get_double("Density");
      require_positive(rho, path + "/Density");
      const ElasticConstants moduli = parse_elastic_constants(prm, path);
      K                             = moduli.K;
      G                             = moduli.G;
      small_strain              = prm.get("Strain measure") == "Small strain";
      const std::string stab    = prm.get("Stabilization");
      stabilization             = stab == "Hourglass" ? 1 : stab == "Silling" ? 2 : 0;
      hourglass_coefficient     = prm.get_double("Hourglass coefficient");
      silling_coefficient       = prm.get_double("Silling coefficient");
      thermal_expansion         = parse_thermal_expansion(prm, path);
      AssertThrow(std::isfinite(hourglass_coefficient) && hourglass_coefficient >= 0,
                  ExcMessage(path + "/Hourglass coefficient must be >= 0, not " + prm.get("Hourglass coefficient")));
      AssertThrow(std::isfinite(silling_coefficient) && silling_coefficient >= 0,
                  ExcMessage(path + "/Silling coefficient must be >= 0, not " + prm.get("Silling coefficient")));
    }

    double
    density() const override
    {
      return rho;
    }
    double
    bulk_modulus() const override
    {
      return K;
    }
    double
    shear_modulus() const override
    {
      return G;
    }
    double
    thermal_expansion_coefficient() const override
    {
      return thermal_expansion;
    }

    std::vector<PointField>
    point_fields() const override
    {
      std::vector<PointField> f = {{"corr_shape_inverse", FieldUse::constant, 9},
                                   {"corr_gershgorin", FieldUse::constant, 1},
                                   {"corr_PKinv", FieldUse::stage, 9},
                                   {"corr_F", FieldUse::stage, 9, "Deformation gradient"},
                                   {"corr_cauchy", FieldUse::local, 9, "Cauchy stress"},
                                   {"corr_energy", FieldUse::local, 1}};
      if (stabilization != 0)
        f.push_back({"corr_live", FieldUse::stage, 1});
      return f;
    }

    void
    initialize(const ModelState &state, const std::vector<unsigned int> &points) override
    {
      AssertThrow(state.bonds.family.empty(),
                  ExcMessage(path + "/Model = Elastic correspondence: blocks of different horizons are not "
                                    "supported (the shape tensor and the force state need one family per bond)"));
      stiffness_horizon = horizon;
      const double *V     = state.cloud.volume.data();
      const bool    partial = !state.bonds.volume_fraction.empty();
      VectorType   &Kinv  = state.fields.get("corr_shape_inverse");
      VectorType   &a     = state.fields.get("corr_gershgorin");
      for (const unsigned int i : points)
        {
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
              message << path << "/Model = Elastic correspondence: the shape tensor K = sum_j xi (x) xi V_j of "
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
    compute_stage(const ModelState &state, const std::vector<unsigned int> &points) const override
    {
      // Compile-time variants keep the bond loop free of branches.
      with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
        constexpr bool P = decltype(periodic)::value;
        if (state.damage)
          stage<BondDamage::continuous, P>(state, points);
        else if (state.broken)
          stage<BondDamage::read, P>(state, points);
        else
          stage<BondDamage::none, P>(state, points);
      });
    }

    bool
    supports_continuous_damage() const override
    {
      return true;
    }

    void
    compute_force(const ModelState &state, const std::vector<unsigned int> &points) const override
    {
      if (state.damage)
        force_variants<BondDamage::continuous>(state, points);
      else if (state.broken)
        force_variants<BondDamage::read>(state, points);
      else
        force_variants<BondDamage::none>(state, points);
    }

    double
    stable_time_step(const ModelState &state, const std::vector<unsigned int> &points) const override
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
      const double     *V     = state.cloud.volume.data();
      const double     *Kinv  = state.fields.get("corr_shape_inverse").begin();
      const double     *a     = state.fields.get("corr_gershgorin").begin();
      const bool        partial = !state.bonds.volume_fraction.empty();
      const double      norm_C  = std::max(3 * K, 2 * G);
      const double      c       = stabilization_constant();
      double            dt      = std::numeric_limits<double>::max();
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

  private:
    std::string path;
    double      rho = 0, K = 0, G = 0;
    bool        small_strain          = false;
    int         stabilization         = 1; // 0 none, 1 hourglass, 2 Silling
    double      hourglass_coefficient = 0.02, silling_coefficient = 0.02, thermal_expansion = 0;
    double      stiffness_horizon     = 0;

    /// c of the stabilization (see the top).
    double
    stabilization_constant() const
    {
      const double d4 = std::pow(stiffness_horizon, 4);
      if (stabilization == 1)
        return 18 * hourglass_coefficient * K / (M_PI * d4);
      if (stabilization == 2)
        return 18 * silling_coefficient * K / (M_PI * d4 * stiffness_horizon);
      return 0;
    }

    /// First Piola-Kirchhoff P, Cauchy stress and energy density W of F
    /// (row-major), with the thermal stretch theta = 1 + alpha dT.
    void
    stress(const double *F, const double theta, double *P, double *sigma, double &W) const
    {
      const double lambda = K - 2 * G / 3;
      double       Fe[9];
      for (unsigned int k = 0; k < 9; ++k)
        Fe[k] = F[k] / theta;
      if (!small_strain)
        {
          double E[9];
          for (unsigned int p = 0; p < 3; ++p)
            for (unsigned int q = 0; q < 3; ++q)
              E[3 * p + q] =
                0.5 * (Fe[p] * Fe[q] + Fe[3 + p] * Fe[3 + q] + Fe[6 + p] * Fe[6 + q] - (p == q ? 1.0 : 0.0));
          const double trE = E[0] + E[4] + E[8];
          double       S[9], EE = 0;
          for (unsigned int k = 0; k < 9; ++k)
            {
              S[k] = 2 * G * E[k] + (k % 4 == 0 ? lambda * trE : 0.0);
              EE += E[k] * E[k];
            }
          multiply(Fe, S, P);
          W = 0.5 * lambda * trE * trE + G * EE;
        }
      else
        {
          // Polar decomposition F_e = R U from the eigensystem of F_e^T F_e.
          SymmetricTensor<2, 3> C;
          for (unsigned int p = 0; p < 3; ++p)
            for (unsigned int q = p; q < 3; ++q)
              C[p][q] = Fe[p] * Fe[q] + Fe[3 + p] * Fe[3 + q] + Fe[6 + p] * Fe[6 + q];
          const auto eig = eigenvectors(C);
          double     U[9] = {}, Uinv[9] = {};
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
          double R[9], eps[9], EE = 0;
          multiply(Fe, Uinv, R);
          for (unsigned int k = 0; k < 9; ++k)
            {
              eps[k] = U[k] - (k % 4 == 0 ? 1.0 : 0.0);
              EE += eps[k] * eps[k];
            }
          const double tr = eps[0] + eps[4] + eps[8];
          double       s_unrot[9], tmp[9], s_rot[9];
          for (unsigned int k = 0; k < 9; ++k)
            s_unrot[k] = 2 * G * eps[k] + (k % 4 == 0 ? lambda * tr : 0.0);
          // sigma = R s R^T; P = J sigma F_e^-T = J sigma (R U)^-T = J sigma R U^-1 (U, R^-T = R).
          double Rt[9];
          for (unsigned int p = 0; p < 3; ++p)
            for (unsigned int q = 0; q < 3; ++q)
              Rt[3 * p + q] = R[3 * q + p];
          multiply(R, s_unrot, tmp);
          multiply(tmp, Rt, s_rot);
          double RUinv[9];
          multiply(R, Uinv, RUinv);
          multiply(s_rot, RUinv, P);
          const double J = determinant(Fe);
          for (unsigned int k = 0; k < 9; ++k)
            P[k] *= J;
          W = 0.5 * lambda * tr * tr + G * EE;
        }
      for (unsigned int k = 0; k < 9; ++k)
        P[k] /= theta;
      // Cauchy stress P F^T / det F.
      const double J = determinant(F);
      for (unsigned int p = 0; p < 3; ++p)
        for (unsigned int q = 0; q < 3; ++q)
          sigma[3 * p + q] = (P[3 * p] * F[3 * q] + P[3 * p + 1] * F[3 * q + 1] + P[3 * p + 2] * F[3 * q + 2]) / J;
    }

    template <BondDamage mode, bool periodic>
    void
    stage(const ModelState &state, const std::vector<unsigned int> &points) const
    {
      const Periodicity   box      = state.cloud.periodicity;
      const double       *X        = state.cloud.X.data();
      const double       *V        = state.cloud.volume.data();
      const double       *u        = state.u;
      const std::size_t  *offsets  = state.bonds.offsets.data();
      const unsigned int *neighbor = state.bonds.neighbor.data();
      const float        *fraction = state.bonds.volume_fraction.empty() ? nullptr : state.bonds.volume_fraction.data();
      const std::uint8_t *broken   = state.broken;
      const double       *d        = state.damage;
      const double       *Kinv0    = state.fields.get("corr_shape_inverse").begin();
      double             *Fs       = state.fields.get("corr_F").begin();
      double             *PK       = state.fields.get("corr_PKinv").begin();
      double             *sigma    = state.fields.get("corr_cauchy").begin();
      double             *Wf       = state.fields.get("corr_energy").begin();
      double             *live     = stabilization != 0 ? state.fields.get("corr_live").begin() : nullptr;
      const double       *eps_T    = state.thermal_strain; // alpha dT per point, or nullptr
      for (const unsigned int i : points)
        {
          const BondOrigin origin(X, u, i);
          double           N[9] = {}, Ks[6] = {};
          for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
            {
              const unsigned int j = neighbor[b];
              double             e[3], y[3];
              bond_vectors<periodic>(X, u, j, origin, box, e, y);
              double w = fraction ? double(fraction[b]) : 1.0;
              if (mode == BondDamage::continuous)
                w *= 1.0 - d[b];
              else if (mode == BondDamage::read)
                w *= 1.0 - broken[b];
              const double wV = w * V[j];
              for (unsigned int p = 0; p < 3; ++p)
                for (unsigned int q = 0; q < 3; ++q)
                  N[3 * p + q] += wV * y[p] * e[q];
              if (mode != BondDamage::none)
                {
                  Ks[0] += wV * e[0] * e[0], Ks[1] += wV * e[1] * e[1], Ks[2] += wV * e[2] * e[2];
                  Ks[3] += wV * e[0] * e[1], Ks[4] += wV * e[1] * e[2], Ks[5] += wV * e[0] * e[2];
                }
            }
          double        Kinv_d[9];
          const double *Kinv = Kinv0 + 9 * i;
          if (mode != BondDamage::none)
            {
              if (!invert_shape(Ks, Kinv_d))
                {
                  // The damaged family no longer spans space: no stress, no stabilization.
                  for (unsigned int k = 0; k < 9; ++k)
                    {
                      Fs[9 * i + k]    = k % 4 == 0 ? 1.0 : 0.0;
                      PK[9 * i + k]    = 0;
                      sigma[9 * i + k] = 0;
                    }
                  Wf[i] = 0;
                  if (live)
                    live[i] = 0;
                  continue;
                }
              Kinv = Kinv_d;
            }
          double *F = Fs + 9 * i;
          multiply(N, Kinv, F);
          double P[9];
          stress(F, eps_T ? 1 + eps_T[i] : 1.0, P, sigma + 9 * i, Wf[i]);
          multiply(P, Kinv, PK + 9 * i);
          if (live)
            live[i] = 1;
        }
    }

    template <BondDamage mode>
    void
    force_variants(const ModelState &state, const std::vector<unsigned int> &points) const
    {
      with_flag(state.energy != nullptr, [&](auto energy) {
        with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
          constexpr bool E = decltype(energy)::value, P = decltype(periodic)::value;
          if (stabilization == 1)
            force<mode, E, P, 1>(state, points);
          else if (stabilization == 2)
            force<mode, E, P, 2>(state, points);
          else
            force<mode, E, P, 0>(state, points);
        });
      });
    }

    /// stab: 0 none, 1 hourglass, 2 Silling.
    template <BondDamage mode, bool energy, bool periodic, int stab>
    void
    force(const ModelState &state, const std::vector<unsigned int> &points) const
    {
      const Periodicity   box      = state.cloud.periodicity;
      const double       *X        = state.cloud.X.data();
      const double       *V        = state.cloud.volume.data();
      const double       *u        = state.u;
      const std::size_t  *offsets  = state.bonds.offsets.data();
      const unsigned int *neighbor = state.bonds.neighbor.data();
      const float        *fraction = state.bonds.volume_fraction.empty() ? nullptr : state.bonds.volume_fraction.data();
      const std::uint8_t *broken   = state.broken;
      const double       *d        = state.damage;
      const double       *PK       = state.fields.get("corr_PKinv").begin();
      const double       *Fs       = state.fields.get("corr_F").begin();
      const double       *Wf       = state.fields.get("corr_energy").begin();
      const double       *live     = stab != 0 ? state.fields.get("corr_live").begin() : nullptr;
      const double        c        = stabilization_constant();
      double             *f        = state.force;
      for (const unsigned int i : points)
        {
          const BondOrigin origin(X, u, i);
          const double    *PKi = PK + 9 * i, *Fi = Fs + 9 * i;
          const double     li  = stab != 0 ? live[i] : 0.0;
          double           fx = 0, fy = 0, fz = 0, Ws = 0;
          for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
            {
              const unsigned int j = neighbor[b];
              double             e[3], y[3];
              bond_vectors<periodic>(X, u, j, origin, box, e, y);
              double w = fraction ? double(fraction[b]) : 1.0;
              if (mode == BondDamage::continuous)
                w *= 1.0 - d[b];
              else if (mode == BondDamage::read)
                w *= 1.0 - broken[b];
              const double  wV  = w * V[j];
              const double *PKj = PK + 9 * j;
              double        t[3];
              for (unsigned int p = 0; p < 3; ++p)
                t[p] = wV * ((PKi[3 * p] + PKj[3 * p]) * e[0] + (PKi[3 * p + 1] + PKj[3 * p + 1]) * e[1] +
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
                        t[p] += c * wV * (zi[p] + zj[p]);
                      if (energy)
                        Ws += wV * (zi[0] * zi[0] + zi[1] * zi[1] + zi[2] * zi[2]);
                    }
                  else
                    {
                      const double r0 = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
                      const double r2 = y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
                      const double k  = c * wV * ((zi[0] + zj[0]) * y[0] + (zi[1] + zj[1]) * y[1] +
                                                 (zi[2] + zj[2]) * y[2]) /
                                       (r0 * r2);
                      for (unsigned int p = 0; p < 3; ++p)
                        t[p] += k * y[p];
                    }
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
  };

  PERIDEAL_REGISTER(Material, ElasticCorrespondence, "Elastic correspondence",
                    "Non-ordinary state-based correspondence model: a nonlocal deformation gradient F = "
                    "(sum w Y (x) xi V) K^-1 and an elastic stress law (St. Venant-Kirchhoff or corotational "
                    "small strain), with hourglass or Silling (2017) stabilization of its zero-energy modes. "
                    "Keys: Density, two of Bulk modulus, Shear modulus, Young's modulus, Poisson's ratio, "
                    "Strain measure, Stabilization, Hourglass coefficient, Silling coefficient, Thermal "
                    "expansion coefficient.")
} // namespace perideal
