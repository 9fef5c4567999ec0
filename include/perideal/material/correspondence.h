#pragma once
// Correspondence materials (state based, non-ordinary; Silling et al. 2007,
// §18; Peridigm's correspondence models): a classical stress law through a
// nonlocal deformation gradient. What every stress law shares lives here and
// in source/material/correspondence.cc; each model file holds only its law
// (elastic_correspondence.cc, elastic_plastic_correspondence.cc).
// With w = omega (1 - d) beta (omega = 1, d the bond damage, beta the partial
// volume fraction), xi = X_j - X_i, Y = y_j - y_i:
//   shape tensor          K_i = sum_j w xi (x) xi V_j
//   deformation gradient  F_i = (sum_j w Y (x) xi V_j) K_i^-1
//   force state           T_ij = w P_i K_i^-1 xi   (P: first Piola-Kirchhoff)
//   force density         f_i = sum_j (T_ij - T_ji) V_j
//                             = sum_j w (P_i K_i^-1 + P_j K_j^-1) xi V_j
// P_j K_j^-1 is a stage field, ghosted before the force pass. Under an affine
// map y = F X, F_i = F exactly at every point, surface points included.
// Since sum_i V_i f_i . du_i = -sum_i V_i P_i : dF_i for any du, the work of
// the forces is that of the stress law on F: a law with P = dW/dF gives a
// potential force.
// Thermal strain: a law sees the thermal stretch theta = 1 + alpha dT_i and
// works with the elastic part F_e = F / theta (a free, uniformly heated body
// has no stress).
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
// reference state with the elastic moduli K, G (stable_time_step()).
// The bond energy of Critical energy (request_bond_energy()): the force on
// the pair is not along the bond, so it is the work the pair's force
// g = (T_ij - T_ji) / (beta V_j) (per unit volume of each end, stabilization
// included; times 1 - d) has done along the relative displacement
// v = Y - xi = u_j - u_i so far,
//   w_NP1 = w_N + (g_N + g_NP1) . (v_NP1 - v_N) / 2   (trapezoid rule per step),
// kept per bond (w, g, v; N and NP1: 112 bytes per bond, for such blocks
// only). Since sum_i V_i f_i . du_i = -sum_i V_i P_i : dF_i, summed over the
// pairs (w beta V_i V_j) it is the work of the stress on F: the stored energy
// plus the plastic dissipation, to the trapezoid rule's error, and Silling's
// stabilization energy; the Hourglass force's work (not a potential force)
// is in w but in no W. The other end computes -g and -v from the same values
// (P_j K_j^-1 is ghosted), so both halves carry the same w bit for bit.

#include <perideal/material/material.h>

#include <cmath>
#include <string>
#include <vector>

namespace perideal
{
  namespace correspondence
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

    /// The von Mises stress sqrt(3 J2) of a Cauchy stress (row-major 3x3;
    /// its symmetric part).
    inline double
    von_mises(const double *s)
    {
      const double a = s[0] - s[4], b = s[4] - s[8], c = s[8] - s[0];
      const double xy = 0.5 * (s[1] + s[3]), yz = 0.5 * (s[5] + s[7]), xz = 0.5 * (s[2] + s[6]);
      return std::sqrt(0.5 * (a * a + b * b + c * c) + 3 * (xy * xy + yz * yz + xz * xz));
    }

    /// Polar decomposition F = R U (row-major 3x3, det F > 0) from the
    /// eigensystem of F^T F: the rotation R, the right stretch U and U^-1.
    void
    polar_decomposition(const double *F, double *R, double *U, double *Uinv);

    /// The raw arrays of a bond loop over the families of a state (one
    /// preamble for every correspondence kernel).
    struct Family
    {
      explicit Family(const ModelState &state)
        : box(state.cloud.periodicity)
        , X(state.cloud.X.data())
        , V(state.cloud.volume.data())
        , u(state.u)
        , offsets(state.bonds.offsets.data())
        , neighbor(state.bonds.neighbor.data())
        , fraction(state.bonds.volume_fraction.empty() ? nullptr : state.bonds.volume_fraction.data())
        , broken(state.broken)
        , d(state.damage)
      {}

      /// 1 - d of bond b (read, breaking: after the fused test).
      template <BondDamage mode>
      double
      intact(const std::size_t b) const
      {
        if (mode == BondDamage::continuous)
          return 1.0 - d[b];
        if (mode != BondDamage::none)
          return 1.0 - broken[b];
        return 1.0;
      }

      /// w = beta (1 - d) of bond b.
      template <BondDamage mode>
      double
      weight(const std::size_t b) const
      {
        return (fraction ? double(fraction[b]) : 1.0) * intact<mode>(b);
      }

      const Periodicity   box;
      const double       *X, *V, *u;
      const std::size_t  *offsets;
      const unsigned int *neighbor;
      const float        *fraction;
      const std::uint8_t *broken;
      const double       *d;
    };
  } // namespace correspondence

  /// The part of a correspondence material that does not depend on its
  /// stress law: shape tensor, F, force assembly, stabilization, stable time
  /// step, and the keys that go with them. A model derives from it, declares
  /// and parses its own law's keys, and implements compute_stage() by
  /// calling compute_deformation() with its law.
  class CorrespondenceMaterial : public Material
  {
  public:
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

    /// The fields of the kinematics (a model appends its own): K^-1,
    /// the Gershgorin row sums, P K^-1 (ghosted), F, the Cauchy stress and
    /// the energy density, and whether the point's family spans space.
    std::vector<PointField>
    point_fields() const override;

    void
    initialize(const ModelState &state, const std::vector<unsigned int> &points) override;

    bool
    supports_continuous_damage() const override
    {
      return true;
    }

    /// The critical stretch runs in the deformation pass (compute_deformation()).
    bool
    fuses_stretch_criterion() const override
    {
      return true;
    }

    void
    compute_force(const ModelState &state, const std::vector<unsigned int> &points) const override;

    double
    stable_time_step(const ModelState &state, const std::vector<unsigned int> &points) const override;

    /// Keeps the bond work (the top) from now on.
    void
    request_bond_energy() override
    {
      work = true;
    }

    bool
    has_bond_energy() const override
    {
      return work;
    }

    /// The latest bond work of the bonds of point @p i.
    void
    bond_energies(const ModelState &state, const unsigned int i, double *w) const override;

    /// The bond work's history, if requested.
    std::vector<BondField>
    bond_fields() const override;

  protected:
    /// @p model: the registered name, for the messages.
    explicit CorrespondenceMaterial(const std::string &model)
      : model(model)
    {}

    /// Declares Density, Stabilization, Hourglass coefficient, Silling
    /// coefficient, Thermal expansion coefficient and the elastic constants
    /// (any two of K, G, E, nu; parse_kinematics_parameters() sets K and G).
    static void
    declare_kinematics_parameters(ParameterHandler &prm);
    /// Parses them (and sets path); the model sets K and G.
    void
    parse_kinematics_parameters(ParameterHandler &prm, const std::string &path);

    /// The stage pass: F_i of every point of @p points into corr_F, then
    /// law(i, F, theta, P, sigma, W) with theta = 1 + alpha dT_i, which
    /// writes the first Piola-Kirchhoff stress P (row-major), the Cauchy
    /// stress sigma (corr_cauchy of i) and the energy density W; then
    /// P K_i^-1 into corr_PKinv and sigma's von Mises stress into
    /// corr_von_mises (a stage field: ghosted, so that both owners of a bond
    /// see both ends' values, for the Von Mises stress damage model). A point whose damaged family does not span
    /// space gets F = I and no stress, and degenerate(i) is called instead.
    template <typename Law, typename Degenerate>
    void
    compute_deformation(const ModelState               &state,
                        const std::vector<unsigned int> &points,
                        const Law                       &law,
                        const Degenerate                &degenerate) const
    {
      with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
        constexpr bool P = decltype(periodic)::value;
        if (state.damage)
          deformation<BondDamage::continuous, P>(state, points, law, degenerate);
        else if (state.breaking)
          deformation<BondDamage::breaking, P>(state, points, law, degenerate);
        else if (state.broken)
          deformation<BondDamage::read, P>(state, points, law, degenerate);
        else
          deformation<BondDamage::none, P>(state, points, law, degenerate);
      });
    }

    std::string path;
    const std::string model;
    double      rho = 0, K = 0, G = 0;
    double      thermal_expansion = 0;

  private:
    bool   work                  = false; // keep each bond's work (request_bond_energy())
    int    stabilization         = 1; // 0 none, 1 hourglass, 2 Silling
    double hourglass_coefficient = 0.02, silling_coefficient = 0.02;
    double stiffness_horizon     = 0;

    /// c of the stabilization (see the top).
    double
    stabilization_constant() const;

    template <BondDamage mode, bool periodic, typename Law, typename Degenerate>
    void
    deformation(const ModelState               &state,
                const std::vector<unsigned int> &points,
                const Law                       &law,
                const Degenerate                &degenerate) const
    {
      using namespace correspondence;
      const Family  fam(state);
      const double *Kinv0 = state.fields.get("corr_shape_inverse").begin();
      double       *Fs    = state.fields.get("corr_F").begin();
      double       *PK    = state.fields.get("corr_PKinv").begin();
      double       *sigma = state.fields.get("corr_cauchy").begin();
      double       *vm    = state.fields.get("corr_von_mises").begin();
      double       *Wf    = state.fields.get("corr_energy").begin();
      double       *live  = stabilization != 0 ? state.fields.get("corr_live").begin() : nullptr;
      const double *eps_T = state.thermal_strain; // alpha dT per point, or nullptr
      std::size_t   newly_broken = 0;
      // A point whose family does not span space: F = I, no stress, no stabilization.
      const auto without_stress = [&](const unsigned int i) {
        for (unsigned int k = 0; k < 9; ++k)
          {
            Fs[9 * i + k]    = k % 4 == 0 ? 1.0 : 0.0;
            PK[9 * i + k]    = 0;
            sigma[9 * i + k] = 0;
          }
        vm[i] = 0;
        Wf[i] = 0;
        if (live)
          live[i] = 0;
      };
      for (const unsigned int i : points)
        {
          if (fam.offsets[i] == fam.offsets[i + 1])
            {
              // A point without bonds (no neighbor within the horizon: it
              // moves freely) has no deformation gradient.
              without_stress(i);
              continue;
            }
          const BondOrigin origin(fam.X, fam.u, i);
          double           N[9] = {}, Ks[6] = {};
          for (std::size_t b = fam.offsets[i]; b < fam.offsets[i + 1]; ++b)
            {
              const unsigned int j = fam.neighbor[b];
              double             e[3], y[3];
              bond_vectors<periodic>(fam.X, fam.u, j, origin, fam.box, e, y);
              if (mode == BondDamage::breaking)
                newly_broken += break_if_overstretched(y[0] * y[0] + y[1] * y[1] + y[2] * y[2],
                                                       e[0] * e[0] + e[1] * e[1] + e[2] * e[2],
                                                       state.breaking->squared_limit, state.breaking->broken[b]);
              const double wV = fam.weight<mode>(b) * fam.V[j];
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
                  without_stress(i);
                  degenerate(i);
                  continue;
                }
              Kinv = Kinv_d;
            }
          double *F = Fs + 9 * i;
          multiply(N, Kinv, F);
          double P[9];
          law(i, static_cast<const double *>(F), eps_T ? 1 + eps_T[i] : 1.0, P, sigma + 9 * i, Wf[i]);
          vm[i] = von_mises(sigma + 9 * i);
          multiply(P, Kinv, PK + 9 * i);
          if (live)
            live[i] = 1;
        }
      if (mode == BondDamage::breaking)
        state.breaking->newly_broken += newly_broken;
    }

    template <BondDamage mode>
    void
    force_variants(const ModelState &state, const std::vector<unsigned int> &points) const;

    /// stab: 0 none, 1 hourglass, 2 Silling; track: update the bond work.
    template <BondDamage mode, bool energy, bool periodic, int stab, bool track>
    void
    force(const ModelState &state, const std::vector<unsigned int> &points) const;
  };
} // namespace perideal
