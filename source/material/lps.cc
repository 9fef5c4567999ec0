// Linear peridynamic solid (state based; Peridigm's "Elastic"), Silling et al.
// 2007. With influence function omega(|xi|/delta), extension e = |y| - |xi|:
//   weighted volume  m_i     = sum_j omega |xi|^2 V_j
//   dilatation       theta_i = (3/m_i) sum_j omega |xi| e (1-d) V_j
//   force state      t_ij    = omega [ (3 K theta_i / m_i) |xi| + (15 G / m_i) e^d ],
//                    e^d     = e - theta_i |xi| / 3
//   force density    f_i     = sum_j (t_ij + t_ji) (1-d) V_j M
//   energy density   W_i     = K theta_i^2 / 2 + (15 G / 2 m_i) sum_j omega (e^d)^2 (1-d) V_j
// with d the bond damage, 0 or 1 (binary damage models) or in [0, 1]
// (continuous ones: the dilatation, the force, the energy and the tangent
// weigh each bond by 1 - d, as Peridigm's elastic.cxx; its force scales the
// deviatoric term by (1-d)^2, the same for binary d, where this one keeps
// (1-d) as the energy has it). The tangent is the secant at fixed d.
// Written as t_ij + t_ji = omega [ |xi| (alpha_i + alpha_j) + (beta_i + beta_j) e ]
// with alpha = theta (3K - 5G)/m (ghosted each step) and beta = 15G/m (ghosted
// once), the neighbor's half uses the neighbor's own moduli and weighted volume.
// The weighted volume is that of the reference configuration (as Peridigm).
// Blocks of different horizons (Bonds::family): m_i and theta_i sum over
// i's own family only, and a bond in one family only carries that end's
// half: t_ij + t_ji = omega_i [|xi| alpha_i + beta_i e] + omega_j [|xi| alpha_j
// + beta_j e], omega_i = 0 if j is not in F(i), omega_j = omega(|xi|/delta_j)
// (the owner's influence function at the other block's horizon) or 0 if i is
// not in F(j); both ends see the same sum, so the bond acts on both.
// Thermal strain: with the free thermal strain eps_T = alpha dT per point
// (ModelState::thermal_strain, dT = T - T_ref, alpha of the point's own
// material), every e above is the mechanical extension e = |y| - |xi| -
// (eps_T,i + eps_T,j)/2 |xi| (the same for both ends, also across blocks of
// different alpha): the dilatation, the deviatoric part, the energy and the
// tangent (whose d e / d y is unchanged; h below takes the mechanical e) all
// see it.
// The moduli: any two of K, G, E, nu (elastic_constants.h).
// Surface correction (optional; Le & Bobaru, Comput. Mech. 61, 2018, energy
// method): under pure shear u = gamma/2 (xi_q e_p + xi_p e_q) the deviatoric
// energy density of point i is (15 G / 2 m_i) gamma^2 (S2 - S1^2/m_i), the
// continuum's G gamma^2 / 2; a family cut by a free surface falls short, and
// G is scaled per point by the ratio, averaged over the shears xy, yz, zx.
// beta_i = 15 g_i G / m_i and gamma_i = (3K - 5 g_i G)/m_i keep the force the
// derivative of the corrected energy.

#include <perideal/base/expression.h>
#include <perideal/material/elastic_constants.h>
#include <perideal/material/material.h>
#include <perideal/neighborhood/bond_pairs.h>

#include <cmath>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class LPS : public Material
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Density", "0", Patterns::Double(), "Mass density rho.");
        declare_elastic_constants(prm);
        declare_thermal_expansion(prm);
        prm.declare_entry("Influence function", "1", Patterns::Anything(),
                          "omega as a muparser expression in r = |xi|/horizon, e.g. "
                          "'1', '1/r', 'exp(-r*r)'. Non-constant functions are "
                          "evaluated once per bond at set-up and stored (8 bytes per bond).");
        prm.declare_entry("Surface correction", "None", Patterns::Selection("None|Energy"),
                          "Energy: scale each point's shear modulus by g = (m/15) / mean over the shears "
                          "xy, yz, zx of (S2 - S1^2/m), S1 = sum_j omega xi_p xi_q V_j, S2 = sum_j omega "
                          "xi_p^2 xi_q^2 / |xi|^2 V_j: the continuum's over the family's deviatoric energy "
                          "density under pure shear (Le & Bobaru 2018's energy method). The dilatation "
                          "needs none: with the weighted volume m summed over the actual family it is "
                          "exact under any isotropic expansion. Free at run time. A plate thinner than two "
                          "horizons is too stiff in its plane with or without it (4 points thick, horizon "
                          "4 h: 24% under uniaxial strain, 31% in shear; doc/models.md).");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path) override
      {
        rho = prm.get_double("Density");
        require_positive(rho, path + "/Density");
        const ElasticConstants moduli = parse_elastic_constants(prm, path);
        K                 = moduli.K;
        G                 = moduli.G;
        thermal_expansion = parse_thermal_expansion(prm, path);
        surface_correction = prm.get("Surface correction") == "Energy";
        influence = std::make_unique<Expression>(prm.get("Influence function"),
                                                 path + "/Influence function",
                                                 0,
                                                 std::vector<std::string>{"r"});
        constant_influence = true;
        const double w1    = influence->value(Point<dim>(1, 0, 0), 0);
        for (const double r : {0.0, 0.1, 0.3, 0.5, 0.7, 0.9})
          if (influence->value(Point<dim>(r, 0, 0), 0) != w1)
            constant_influence = false;
        omega0 = w1;
        AssertThrow(std::isfinite(omega0) && (omega0 > 0 || !constant_influence),
                    ExcMessage(path + "/Influence function must be positive"));
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
      thermal_expansion_coefficient() const override
      {
        return thermal_expansion;
      }
      double
      shear_modulus() const override
      {
        return G;
      }

      void
      initialize(const ModelState &state, const std::vector<unsigned int> &points) override
      {
        const double *V = state.cloud.volume.data();
        // With partial volumes the per-bond omega carries beta_ij too: every
        // family sum (m, theta, force, tangent, stable step) then weighs
        // neighbor j with beta_ij V_j and nothing else changes.
        const bool partial = !state.bonds.volume_fraction.empty();
        // Different horizons: omega per bond and per half (zero where the bond
        // is not in that end's family), so the kernels need no bit test.
        halves = !state.bonds.family.empty();
        if (partial || halves)
          constant_influence = false;
        // Partial volumes and half bonds keep directed families: their two
        // halves need not weigh the same.
        if (partial || halves)
          pairs.clear();
        else
          pairs.reinit(state.cloud, state.bonds, points, block);
        if (!constant_influence)
          omega.assign(state.bonds.n_bonds(), 0.0);
        if (halves)
          omega_other.assign(state.bonds.n_bonds(), 0.0);
        VectorType &m     = state.fields.get("weighted_volume");
        VectorType &beta  = state.fields.get("lps_beta");
        VectorType &gamma = state.fields.get("lps_gamma");
        VectorType &D     = state.fields.get("lps_coupling");
        for (const unsigned int i : points)
          {
            double mi = 0, Ai = 0, S1[3] = {0, 0, 0}, S2[3] = {0, 0, 0};
            for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
              {
                const unsigned int j  = state.bonds.neighbor[b];
                const auto         xi = state.cloud.bond_vector(i, j);
                const double       ex = xi[0], ey = xi[1], ez = xi[2];
                const double       r0 = std::sqrt(ex * ex + ey * ey + ez * ez);
                double             w  = omega0;
                if (halves)
                  {
                    const double delta_j = state.bonds.block_horizon[state.cloud.block[j]];
                    omega_other[b] = state.bonds.family[b] & Bonds::other_half ?
                                       influence->value(Point<dim>(std::min(r0 / delta_j, 1.0), 0, 0), 0) :
                                       0.0;
                  }
                if (!constant_influence)
                  {
                    // Partial volumes add bonds up to a cell radius beyond the
                    // horizon; they take omega at the horizon.
                    const double r = std::min(r0 / horizon, 1.0);
                    w = influence->value(Point<dim>(r, 0, 0), 0);
                    AssertThrow(std::isfinite(w) && w >= 0,
                                ExcMessage(influence->key() + ": '" + influence->text() +
                                           "' is negative or not finite at r = " + std::to_string(r)));
                    if (partial)
                      w *= state.bonds.volume_fraction[b];
                    if (halves && !(state.bonds.family[b] & Bonds::own_half))
                      w = 0;
                    omega[b] = w;
                  }
                mi += w * r0 * r0 * V[j];
                Ai += w * r0 * V[j];
                if (surface_correction)
                  {
                    const double e[3] = {ex, ey, ez};
                    for (unsigned int p = 0; p < 3; ++p)
                      {
                        const double pq = e[p] * e[(p + 1) % 3];
                        S1[p] += w * pq * V[j];
                        S2[p] += w * pq * pq / (r0 * r0) * V[j];
                      }
                  }
              }
            // m_i = 0 only for a virtual point of the FE coupling left without
            // bonds (the core stops a run with any other point without bonds):
            // it carries no energy and no force state.
            const double inverse   = mi > 0 ? 1 / mi : 0.0;
            // Surface correction of the shear modulus (see the top).
            double g = 1;
            if (surface_correction && mi > 0)
              {
                double deficit = 0;
                for (unsigned int p = 0; p < 3; ++p)
                  deficit += S2[p] - S1[p] * S1[p] * inverse;
                if (deficit > 0)
                  g = 3 * mi / 15 / deficit;
              }
            m.local_element(i)     = mi;
            beta.local_element(i)  = 15 * g * G * inverse;
            gamma.local_element(i) = (3 * K - 5 * g * G) * inverse;
            D.local_element(i)     = std::abs(3 * K - 5 * g * G) * inverse * Ai * inverse;
          }
      }

      std::vector<PointField>
      point_fields() const override
      {
        return {{"dilatation", FieldUse::local, 1, "Dilatation"},
                {"weighted_volume", FieldUse::constant, 1, "Weighted volume"},
                {"lps_beta", FieldUse::constant},
                {"lps_gamma", FieldUse::constant},
                {"lps_coupling", FieldUse::constant},
                {"lps_alpha", FieldUse::stage}};
      }

      void
      compute_stage(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        // Compile-time variants keep the bond loop free of branches.
        with_flag(!constant_influence, [&](auto weighted) {
          with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
            with_flag(thermal(state), [&](auto heated) {
              constexpr bool W = decltype(weighted)::value, P = decltype(periodic)::value,
                             T = decltype(heated)::value;
              if (state.breaking && state.breaking->by_block())
                dilatation<BondDamage::breaking_by_block, W, P, T>(state, points);
              else if (state.breaking)
                dilatation<BondDamage::breaking, W, P, T>(state, points);
              else if (state.damage)
                dilatation<BondDamage::continuous, W, P, T>(state, points);
              else if (state.broken)
                dilatation<BondDamage::read, W, P, T>(state, points);
              else
                dilatation<BondDamage::none, W, P, T>(state, points);
            });
          });
        });
      }

      bool
      fuses_stretch_criterion() const override
      {
        return true;
      }

      bool
      fuses_limits_by_block() const override
      {
        return true;
      }

      bool
      supports_continuous_damage() const override
      {
        return true;
      }

      bool
      has_bond_energy() const override
      {
        return true;
      }

      /// w = t e / 2 with t = t_ij + t_ji the bond's scalar force state (both
      /// halves, as compute_force()) and e its mechanical extension: summed
      /// over a point's family, sum_j t_ij e V_j / 2 is its energy density
      /// W_i exactly (doc/models.md), so the pairs share the strain energy.
      void
      bond_energies(const ModelState &state, const unsigned int i, double *w) const override
      {
        with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
          with_flag(thermal(state), [&](auto heated) {
            constexpr bool P = decltype(periodic)::value, T = decltype(heated)::value;
            if (state.damage)
              energy_kernel<P, T, BondDamage::continuous>(state, i, w);
            else if (state.broken)
              energy_kernel<P, T, BondDamage::read>(state, i, w);
            else
              energy_kernel<P, T, BondDamage::none>(state, i, w);
          });
        });
      }

      bool
      weight_energy(const ModelState &state, const std::vector<unsigned int> &points, const double *weight) override
      {
        // The force state of point i is omega (gamma_i theta_i |xi| + beta_i e):
        // scaling beta_i and gamma_i by w_i weights its energy by w_i; the
        // force and the tangent read them from the fields.
        VectorType &beta  = state.fields.get("lps_beta");
        VectorType &gamma = state.fields.get("lps_gamma");
        VectorType &D     = state.fields.get("lps_coupling");
        for (const unsigned int i : points)
          {
            beta.local_element(i) *= weight[i];
            gamma.local_element(i) *= weight[i];
            D.local_element(i) *= weight[i];
          }
        energy_weighted = true;
        return true;
      }

      void
      compute_force(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        // Compile-time variants keep the bond loop free of branches.
        if (state.damage)
          force_variants<BondDamage::continuous>(state, points);
        else if (state.broken)
          force_variants<BondDamage::read>(state, points);
        else
          force_variants<BondDamage::none>(state, points);
      }

      /// One pass over the points' bonds, nothing written. With B = sum_j w
      /// e^2 V_j, D = sum_j w |xi|^2 V_j and theta = 3 A / m, A = sum_j w |xi|
      /// e V_j, over the weighted bonds (w = omega (1 - d), as the energy of
      /// compute_force()), the deviatoric sum is sum_j w (e^d)^2 V_j = B +
      /// theta^2 (D - 2 m) / 9, so W(before) - W(now) = K (theta_b^2 -
      /// theta_n^2) / 2 + beta / 2 [dB + ((theta_b^2 - theta_n^2)(D_n - 2 m)
      /// + theta_b^2 dD) / 9] with dA, dB, dD the changed bonds' share (their
      /// weight before minus now): no difference of two large sums.
      double
      released_energy(const ModelState &before, const ModelState &now, const std::vector<unsigned int> &points) const override
      {
        double e = 0;
        with_flag(now.cloud.periodicity.any(), [&](auto periodic) {
          with_flag(thermal(now), [&](auto heated) {
            constexpr bool P = decltype(periodic)::value, T = decltype(heated)::value;
            e = now.damage ? released<P, T, BondDamage::continuous>(before, now, points) :
                             released<P, T, BondDamage::read>(before, now, points);
          });
        });
        return e;
      }

      double
      stable_time_step(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        // Gershgorin bound of the linearized LPS tangent, row by row:
        //   rho_i lambda_i <= 2 sum_j (beta_i + beta_j) omega V_j           (pairwise part)
        //                   + 6 |gamma_i| A_i^2 / m_i                        (own dilatation)
        //                   + 6 sum_j omega |xi| V_j |gamma_j| A_j / m_j     (neighbors' dilatation)
        // with A_i = sum_j omega |xi| V_j; the central difference limit is 2/sqrt(lambda).
        const double     *V     = state.cloud.volume.data();
        const VectorType &beta  = state.fields.get("lps_beta");
        const VectorType &gamma = state.fields.get("lps_gamma");
        const VectorType &m     = state.fields.get("weighted_volume");
        const VectorType &D     = state.fields.get("lps_coupling");
        double            dt    = std::numeric_limits<double>::max();
        for (const unsigned int i : points)
          {
            double pair = 0, Ai = 0, neighbors = 0;
            for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
              {
                const unsigned int j  = state.bonds.neighbor[b];
                const double       r0 = state.cloud.bond_vector(i, j).norm();
                const double       w  = constant_influence ? omega0 : omega[b];
                if (halves)
                  {
                    const double w2 = omega_other[b];
                    pair += (beta.local_element(i) * w + beta.local_element(j) * w2) * V[j];
                    Ai += w * r0 * V[j];
                    neighbors += w2 * r0 * V[j] * D.local_element(j);
                    continue;
                  }
                pair += (beta.local_element(i) + beta.local_element(j)) * w * V[j];
                Ai += w * r0 * V[j];
                neighbors += w * r0 * V[j] * D.local_element(j);
              }
            const double lambda = (2 * pair + 6 * std::abs(gamma.local_element(i)) * Ai * Ai /
                                                m.local_element(i) +
                                   6 * neighbors) /
                                  rho;
            if (lambda > 0)
              dt = std::min(dt, 2 / std::sqrt(lambda));
          }
        return dt;
      }

      bool
      add_tangent(const ModelState &state, const std::vector<unsigned int> &points, TangentRows &rows) const override
      {
        // Owner i, bond j (w = omega (1 - d), M = y/|y|, e = |y| - |xi|), from
        // f_i = sum_j V_j h_ij M_ij, h_ij = w [|xi| (alpha_i + alpha_j) + (beta_i + beta_j) e]:
        //   direct     A_j = V_j [w (beta_i + beta_j) M M^T + h (I - M M^T) / |y|]
        //   dilatation theta_i depends on u_l, l in F(i), through
        //              g_l = d theta_i / d u_l = (3/m_i) w_l |xi_l| V_l M_l, g_i = -sum_l g_l = -G;
        //              f_i through alpha_i:  c = sum_j V_j w |xi| gamma_i M_j  (d f_i / d theta_i)
        //              f_j through alpha_i:  -q_j, q_j = V_i w |xi| gamma_i M_j  (d f_j / d theta_i)
        // K = -d(V f)/du:  row i:  K_il = -V_i (A_l + c g_l^T),  K_ii = V_i (sum A + c G^T)
        //                  row j:  K_jl =  V_j q_j g_l^T,        K_ji = -V_j q_j G^T
        // Different horizons: h has a half per end, w_i (i's, over F(i): the
        // only one theta_i sees) and w_j (j's), so A_j = V_j [(w_i beta_i +
        // w_j beta_j) M M^T + h (I - M M^T)/|y|], and c, g use w_i. Row j of
        // f_j through theta_i is bond j->i's other half, whose weight is i->j's
        // own one: j in F(i) and theta_i's weight for it.
        const double *V     = state.cloud.volume.data();
        const double *u     = state.u;
        const double *m     = state.fields.get("weighted_volume").begin();
        const double *alpha = state.fields.get("lps_alpha").begin();
        const double *beta  = state.fields.get("lps_beta").begin();
        const double *gamma = state.fields.get("lps_gamma").begin();
        std::vector<unsigned int> cols;
        std::vector<double>       blocks, M, g, w_r0; // w_r0: omega (1 - d) |xi| per bond
        for (const unsigned int i : points)
          {
            const std::size_t first = state.bonds.offsets[i], n = state.bonds.offsets[i + 1] - first;
            cols.resize(n + 1);
            blocks.assign(9 * (n + 1), 0.0);
            M.assign(3 * n, 0.0);
            g.assign(3 * n, 0.0);
            w_r0.assign(n, 0.0);
            cols[0] = i;
            double c[3] = {0, 0, 0}, Gs[3] = {0, 0, 0};
            for (std::size_t k = 0; k < n; ++k)
              {
                const std::size_t  b = first + k;
                const unsigned int j = state.bonds.neighbor[b];
                cols[k + 1]          = j;
                double w             = constant_influence ? omega0 : omega[b];
                double w2            = halves ? omega_other[b] : 0.0;
                // Continuous damage: the secant stiffness at fixed d.
                const double intact = state.damage ? 1.0 - state.damage[b] : state.broken ? 1.0 - state.broken[b] : 1.0;
                w *= intact;
                w2 *= intact;
                double xi[3], y[3];
                const auto [r0, r] = bond_geometry(state.cloud, u, i, j, xi, y);
                const double e     = r - r0 - thermal_extension(state, i, j, r0);
                const double h     = halves ? w * (r0 * alpha[i] + beta[i] * e) + w2 * (r0 * alpha[j] + beta[j] * e) :
                                              w * (r0 * (alpha[i] + alpha[j]) + (beta[i] + beta[j]) * e);
                const double w_beta = halves ? w * beta[i] + w2 * beta[j] : w * (beta[i] + beta[j]);
                w_r0[k]            = w * r0;
                for (unsigned int d = 0; d < 3; ++d)
                  {
                    M[3 * k + d] = y[d] / r;
                    g[3 * k + d] = 3 / m[i] * w * r0 * V[j] * M[3 * k + d];
                    Gs[d] += g[3 * k + d];
                    c[d] += V[j] * w * r0 * gamma[i] * M[3 * k + d];
                  }
                for (unsigned int p = 0; p < 3; ++p)
                  for (unsigned int q = 0; q < 3; ++q)
                    {
                      const double MM = M[3 * k + p] * M[3 * k + q];
                      const double A  = V[i] * V[j] * (w_beta * MM + h * ((p == q) - MM) / r);
                      blocks[9 * (k + 1) + 3 * p + q] = -A;
                      blocks[3 * p + q] += A;
                    }
              }
            // Row i: the dilatation of i.
            for (std::size_t l = 0; l < n; ++l)
              for (unsigned int p = 0; p < 3; ++p)
                for (unsigned int q = 0; q < 3; ++q)
                  blocks[9 * (l + 1) + 3 * p + q] -= V[i] * c[p] * g[3 * l + q];
            for (unsigned int p = 0; p < 3; ++p)
              for (unsigned int q = 0; q < 3; ++q)
                blocks[3 * p + q] += V[i] * c[p] * Gs[q];
            rows.add(i, cols.data(), blocks.data(), n + 1);

            // Rows j: their force through the dilatation of i.
            if (gamma[i] == 0)
              continue;
            for (std::size_t k = 0; k < n; ++k)
              {
                if (w_r0[k] == 0)
                  continue;
                const unsigned int j = cols[k + 1];
                const double       s = V[j] * V[i] * w_r0[k] * gamma[i];
                for (unsigned int p = 0; p < 3; ++p)
                  {
                    const double qp = s * M[3 * k + p];
                    for (unsigned int q = 0; q < 3; ++q)
                      {
                        blocks[3 * p + q] = -qp * Gs[q];
                        for (std::size_t l = 0; l < n; ++l)
                          blocks[9 * (l + 1) + 3 * p + q] = qp * g[3 * l + q];
                      }
                  }
                rows.add(j, cols.data(), blocks.data(), n + 1);
              }
          }
        return true;
      }

    private:
      double                      rho = 0, K = 0, G = 0, thermal_expansion = 0;
      std::unique_ptr<Expression> influence;
      bool                        constant_influence = true;
      double                      omega0             = 1;
      std::vector<double>         omega; // per bond, only for a non-constant influence function
      std::vector<double>         omega_other; // per bond, the other end's half: only with Bonds::family
      bool                        halves = false; // Bonds::family is set: omega and omega_other hold the halves
      bool                        energy_weighted = false; // weight_energy() scaled the fields
      bool                        surface_correction = false;

      bool
      thermal(const ModelState &state) const
      {
        return state.thermal_strain != nullptr;
      }
      /// The free thermal extension of bond i-j, 0 without thermal strain (tangent).
      double
      thermal_extension(const ModelState &state, const unsigned int i, const unsigned int j, const double r0) const
      {
        return thermal(state) ?
                 0.5 * (state.thermal_strain[i] + state.thermal_strain[j]) * r0 :
                 0.0;
      }

      template <BondDamage mode, bool weighted, bool periodic, bool heated>
      void
      dilatation(const ModelState &state, const std::vector<unsigned int> &points) const
      {
        if (pairs.serves(points))
          {
            pair_dilatation<mode, weighted, periodic, heated>(state, points);
            return;
          }
        const Periodicity   box      = state.cloud.periodicity;
        const double       *X        = state.cloud.X.data();
        const double       *V        = state.cloud.volume.data();
        const double       *u        = state.u;
        const std::size_t  *offsets  = state.bonds.offsets.data();
        const unsigned int *neighbor = state.bonds.neighbor.data();
        constexpr bool      by_block = mode == BondDamage::breaking_by_block;
        const auto [broken, damage, limit, limit_at] = bond_damage_view<mode>(state);
        const double       *d        = state.damage; // continuous only
        const double       *w_bond   = omega.data();
        const double       *m        = state.fields.get("weighted_volume").begin();
        const double       *gamma    = state.fields.get("lps_gamma").begin();
        double             *theta    = state.fields.get("dilatation").begin();
        double             *alpha    = state.fields.get("lps_alpha").begin();
        const double       *eps_T    = state.thermal_strain; // heated only
        std::size_t         newly_broken = 0;
        for (const unsigned int i : points)
          {
            const BondOrigin origin(X, u, i);
            double           sum = 0;
  #pragma omp simd reduction(+ : sum, newly_broken)
            for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
              {
                const unsigned int j = neighbor[b];
                double             e[3], y[3];
                bond_vectors<periodic>(X, u, j, origin, box, e, y);
                const double ex = e[0], ey = e[1], ez = e[2], dx = y[0], dy = y[1], dz = y[2];
                const double       r0sq = ex * ex + ey * ey + ez * ez;
                const double       rsq  = dx * dx + dy * dy + dz * dz;
                if (breaks(mode))
                  newly_broken += break_if_overstretched(rsq, r0sq, by_block ? limit_at[j] : limit, broken[b]);
                const double r0 = std::sqrt(r0sq);
                const double r  = std::sqrt(rsq);
                double       w  = weighted ? w_bond[b] : omega0;
                if (mode == BondDamage::continuous)
                  w *= 1.0 - d[b];
                else if (mode != BondDamage::none)
                  w *= 1.0 - damage[b];
                const double ext = heated ? r - r0 - 0.5 * (eps_T[i] + eps_T[j]) * r0 : r - r0;
                sum += w * r0 * ext * V[j];
              }
            theta[i] = m[i] > 0 ? 3 * sum / m[i] : 0.0;
            alpha[i] = gamma[i] * theta[i];
          }
        if (breaks(mode))
          state.breaking->newly_broken += newly_broken;
      }

      /// bond_energies() of point @p i: force()'s bond scalar t (both halves)
      /// times e / 2; with partial volumes per unit volume (omega carries beta).
      template <bool periodic, bool heated, BondDamage mode>
      void
      energy_kernel(const ModelState &state, const unsigned int i, double *w_out) const
      {
        const Periodicity   box      = state.cloud.periodicity;
        const double       *X        = state.cloud.X.data();
        const double       *u        = state.u;
        const unsigned int *neighbor = state.bonds.neighbor.data();
        const double       *alpha    = state.fields.get("lps_alpha").begin();
        const double       *beta     = state.fields.get("lps_beta").begin();
        const double       *w_bond   = constant_influence ? nullptr : omega.data();
        const double       *w_other  = halves ? omega_other.data() : nullptr;
        const float        *fraction = state.bonds.volume_fraction.empty() ? nullptr : state.bonds.volume_fraction.data();
        const double       *d        = state.damage;
        const std::uint8_t *broken   = state.broken;
        const double       *eps_T    = state.thermal_strain; // heated only
        const std::size_t   first    = state.bonds.offsets[i], last = state.bonds.offsets[i + 1];
        const BondOrigin    origin(X, u, i);
  #pragma omp simd
        for (std::size_t b = first; b < last; ++b)
          {
            const unsigned int j = neighbor[b];
            double             ev[3], y[3];
            bond_vectors<periodic>(X, u, j, origin, box, ev, y);
            const double r0 = std::sqrt(ev[0] * ev[0] + ev[1] * ev[1] + ev[2] * ev[2]);
            const double r  = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
            const double e  = heated ? r - r0 - 0.5 * (eps_T[i] + eps_T[j]) * r0 : r - r0;
            const double intact = mode == BondDamage::none       ? 1.0 :
                                  mode == BondDamage::continuous ? 1.0 - d[b] :
                                                                   1.0 - broken[b];
            const double wi = intact * (w_bond ? w_bond[b] : omega0);
            const double t  = w_other ? wi * (r0 * alpha[i] + beta[i] * e) +
                                         intact * w_other[b] * (r0 * alpha[j] + beta[j] * e) :
                                        wi * (r0 * (alpha[i] + alpha[j]) + (beta[i] + beta[j]) * e);
            w_out[b - first] = 0.5 * t * e / (fraction && fraction[b] > 0 ? double(fraction[b]) : 1.0);
          }
      }

      template <bool periodic, bool heated, BondDamage mode>
      double
      released(const ModelState &before, const ModelState &now, const std::vector<unsigned int> &points) const
      {
        const Periodicity   box      = now.cloud.periodicity;
        const double       *X        = now.cloud.X.data();
        const double       *V        = now.cloud.volume.data();
        const double       *u        = now.u;
        const std::size_t  *offsets  = now.bonds.offsets.data();
        const unsigned int *neighbor = now.bonds.neighbor.data();
        const double       *w_bond   = constant_influence ? nullptr : omega.data();
        const double       *m        = now.fields.get("weighted_volume").begin();
        const double       *beta     = now.fields.get("lps_beta").begin();
        const double       *gamma    = now.fields.get("lps_gamma").begin();
        const double       *eps_T    = now.thermal_strain; // heated only
        double              released = 0;
        for (const unsigned int i : points)
          {
            if (!(m[i] > 0))
              continue; // a virtual point without bonds: no energy
            const BondOrigin origin(X, u, i);
            double           A = 0, D = 0, dA = 0, dB = 0, dD = 0;
  #pragma omp simd reduction(+ : A, D, dA, dB, dD)
            for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
              {
                const unsigned int j = neighbor[b];
                double             ev[3], y[3];
                bond_vectors<periodic>(X, u, j, origin, box, ev, y);
                const double r0sq = ev[0] * ev[0] + ev[1] * ev[1] + ev[2] * ev[2];
                const double r0   = std::sqrt(r0sq);
                const double r    = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
                const double e    = heated ? r - r0 - 0.5 * (eps_T[i] + eps_T[j]) * r0 : r - r0;
                const double w0   = (w_bond ? w_bond[b] : omega0) * V[j];
                const double wn   = w0 * (mode == BondDamage::continuous ? 1.0 - now.damage[b] : 1.0 - now.broken[b]);
                const double dw   = w0 * (mode == BondDamage::continuous ? now.damage[b] - before.damage[b] :
                                                                           double(now.broken[b]) - before.broken[b]);
                A += wn * r0 * e;
                D += wn * r0sq;
                dA += dw * r0 * e;
                dB += dw * e * e;
                dD += dw * r0sq;
              }
            const double theta_n = 3 * A / m[i], theta_b = theta_n + 3 * dA / m[i];
            const double squares = (theta_b - theta_n) * (theta_b + theta_n);
            // Weighted: w_i K = m_i (gamma_i + beta_i / 3) / 3 of the scaled fields (as compute_force()).
            const double Ki = energy_weighted ? m[i] * (gamma[i] + beta[i] / 3) / 3 : K;
            released += V[i] * (0.5 * Ki * squares +
                                0.5 * beta[i] * (dB + (squares * (D - 2 * m[i]) + theta_b * theta_b * dD) / 9));
          }
        return released;
      }

      template <BondDamage mode>
      void
      force_variants(const ModelState &state, const std::vector<unsigned int> &points) const
      {
        with_flag(state.energy != nullptr, [&](auto energy) {
          with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
            with_flag(thermal(state), [&](auto heated) {
              constexpr bool E = decltype(energy)::value, P = decltype(periodic)::value, T = decltype(heated)::value;
              if (halves)
                force<mode, E, true, P, T, true>(state, points);
              else if (constant_influence)
                force<mode, E, false, P, T>(state, points);
              else
                force<mode, E, true, P, T>(state, points);
            });
          });
        });
      }

      /// mode: none, read (state.broken) or continuous (state.damage).
      template <BondDamage mode, bool energy, bool weighted, bool periodic, bool heated, bool two_halves = false>
      void
      force(const ModelState &state, const std::vector<unsigned int> &points) const
      {
        if constexpr (!two_halves)
          if (pairs.serves(points))
            {
              pair_force<mode, energy, weighted, periodic, heated>(state, points);
              return;
            }
        const Periodicity   box      = state.cloud.periodicity;
        const double       *X        = state.cloud.X.data();
        const double       *V        = state.cloud.volume.data();
        const double       *u        = state.u;
        const std::size_t  *offsets  = state.bonds.offsets.data();
        const unsigned int *neighbor = state.bonds.neighbor.data();
        const std::uint8_t *broken   = state.broken;
        const double       *d        = state.damage; // continuous only
        const double       *w_bond   = omega.data();
        const double       *w_other  = omega_other.data();
        const double       *alpha    = state.fields.get("lps_alpha").begin();
        const double       *beta     = state.fields.get("lps_beta").begin();
        const double       *theta    = state.fields.get("dilatation").begin();
        const double       *m        = state.fields.get("weighted_volume").begin();
        const double       *gamma    = state.fields.get("lps_gamma").begin();
        double             *f        = state.force;
        const double       *eps_T    = state.thermal_strain; // heated only
        for (const unsigned int i : points)
          {
            const BondOrigin origin(X, u, i);
            const double     ai = alpha[i], bi = beta[i];
            const double     third_theta = theta[i] / 3;
            double           fx = 0, fy = 0, fz = 0, Wd = 0;
  #pragma omp simd reduction(+ : fx, fy, fz, Wd)
            for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
              {
                const unsigned int j = neighbor[b];
                double             ev[3], y[3];
                bond_vectors<periodic>(X, u, j, origin, box, ev, y);
                const double ex = ev[0], ey = ev[1], ez = ev[2], dx = y[0], dy = y[1], dz = y[2];
                const double       r0 = std::sqrt(ex * ex + ey * ey + ez * ez);
                const double       r  = std::sqrt(dx * dx + dy * dy + dz * dz);
                const double       e  = heated ? r - r0 - 0.5 * (eps_T[i] + eps_T[j]) * r0 : r - r0;
                double             w  = weighted ? w_bond[b] : omega0;
                double             w2 = two_halves ? w_other[b] : 0.0;
                if (mode != BondDamage::none)
                  {
                    const double intact = mode == BondDamage::continuous ? 1.0 - d[b] : 1.0 - broken[b];
                    w *= intact;
                    w2 *= intact;
                  }
                const double t = two_halves ? w * (r0 * ai + bi * e) + w2 * (r0 * alpha[j] + beta[j] * e) :
                                              w * (r0 * (ai + alpha[j]) + (bi + beta[j]) * e);
                const double k = t * V[j] / r;
                fx += k * dx;
                fy += k * dy;
                fz += k * dz;
                if (energy)
                  {
                    const double ed = e - third_theta * r0;
                    Wd += w * ed * ed * V[j];
                  }
              }
            f[3 * i] += fx;
            f[3 * i + 1] += fy;
            f[3 * i + 2] += fz;
            if (energy)
              {
                // Weighted: w_i K = m_i (gamma_i + beta_i / 3) / 3 of the scaled fields.
                const double Ki = energy_weighted ? m[i] * (gamma[i] + bi / 3) / 3 : K;
                state.energy[i] += 0.5 * Ki * theta[i] * theta[i] + 0.5 * bi * Wd;
              }
          }
      }

      /// What the pair loops read and write besides PairLoopData, taken once
      /// per pass.
      struct PairData : PairLoopData
      {
        const double *w_bond; // weighted only
        double        omega0;
        const double *alpha, *beta, *theta; // force pass
        double       *sum;                  // dilatation pass: sum_j w |xi| e V_j
        double       *energy;               // force pass
      };

      template <BondDamage mode>
      PairData
      pair_data(const ModelState &state) const
      {
        return {pair_loop_data<mode>(state, pairs), omega.data(), omega0, nullptr, nullptr, nullptr, nullptr,
                state.energy};
      }

      /// The weight omega (1 - d) of bond b.
      template <BondDamage mode, bool weighted>
      static double
      bond_weight(const PairData &p, const std::size_t b)
      {
        const double w = weighted ? p.w_bond[b] : p.omega0;
        return mode == BondDamage::none       ? w :
               mode == BondDamage::continuous ? w * (1.0 - p.d[b]) :
                                                w * (1.0 - p.damage[b]);
      }

      /// dilatation() with each bond between two points of the list
      /// evaluated once (BondPairs): w |xi| e is added to the sums of both
      /// ends, with V_j to i's and V_i to j's; then theta = 3 sum / m.
      template <BondDamage mode, bool weighted, bool periodic, bool heated>
      void
      pair_dilatation(const ModelState &state, const std::vector<unsigned int> &points) const
      {
        PairData p     = pair_data<mode>(state);
        double  *theta = state.fields.get("dilatation").begin();
        p.sum         = theta;
        for (const unsigned int i : points)
          theta[i] = 0;
        const std::size_t newly_broken =
          pairs.for_each_part(state.cloud, state.bonds, points, p.broken, [&](auto part, auto... range) {
            return pair_dilatation_loop<decltype(part)::value, mode, weighted, periodic, heated>(p, range...);
          });
        const double *m     = state.fields.get("weighted_volume").begin();
        const double *gamma = state.fields.get("lps_gamma").begin();
        double       *alpha = state.fields.get("lps_alpha").begin();
        for (const unsigned int i : points)
          {
            theta[i] = m[i] > 0 ? 3 * theta[i] / m[i] : 0.0;
            alpha[i] = gamma[i] * theta[i];
          }
        if (breaks(mode))
          state.breaking->newly_broken += newly_broken;
      }

      /// The bonds [from, last) of point i, the @p part of its family, in
      /// the dilatation's sums; returns the halves newly broken. Vectorized
      /// over the bonds with gathers and scatters as PMB's pair loop: no two
      /// bonds of a family share a far end, and a masked bond adds +0 to i.
      template <PairPart part, BondDamage mode, bool weighted, bool periodic, bool heated>
      static std::size_t
      pair_dilatation_loop(const PairData &p, const unsigned int i, const std::size_t from, const std::size_t last)
      {
        constexpr bool   masked = pair_masked(part), scatter = pair_scatters(part);
        constexpr bool   by_block = mode == BondDamage::breaking_by_block;
        const BondOrigin origin(p.X, p.u, i);
        const double     Vi  = p.V[i];
        double           sum = 0;
        std::size_t      newly = 0;
  #pragma omp simd reduction(+ : sum, newly)
        for (std::size_t b = from; b < last; ++b)
          {
            const unsigned int j = p.neighbor[b];
            unsigned int       on_i, on_j;
            pair_shares<part>(masked && p.listed(j), on_i, on_j);
            double e[3], y[3];
            bond_vectors<periodic>(p.X, p.u, j, origin, p.box, e, y);
            const double r0sq = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
            const double rsq  = y[0] * y[0] + y[1] * y[1] + y[2] * y[2];
            if (breaks(mode))
              newly += (on_i + on_j) * break_if_overstretched(rsq, r0sq, by_block ? p.limit_at[j] : p.limit, p.broken[b]);
            const double r0  = std::sqrt(r0sq);
            const double r   = std::sqrt(rsq);
            const double ext = heated ? r - r0 - 0.5 * (p.eps_T[i] + p.eps_T[j]) * r0 : r - r0;
            const double    wx  = bond_weight<mode, weighted>(p, b) * r0 * ext;
            const PairSplit add = split_pair<masked>(wx, Vi, p.V[j], i, j, on_i, on_j);
            sum += add.on_i;
            if constexpr (scatter)
              p.sum[add.target] += add.on_j;
          }
        p.sum[i] += sum;
        return newly;
      }

      /// force() with each bond between two points of the list evaluated
      /// once (BondPairs): the bond's scalar t = t_ij + t_ji is the same for
      /// both ends; t y / r is added to i with V_j and taken from j with V_i,
      /// and each end's deviatoric energy takes its own theta.
      template <BondDamage mode, bool energy, bool weighted, bool periodic, bool heated>
      void
      pair_force(const ModelState &state, const std::vector<unsigned int> &points) const
      {
        PairData p = pair_data<mode>(state);
        p.alpha    = state.fields.get("lps_alpha").begin();
        p.beta     = state.fields.get("lps_beta").begin();
        p.theta    = state.fields.get("dilatation").begin();
        pairs.for_each_part(state.cloud, state.bonds, points, nullptr, [&](auto part, auto... range) {
          pair_force_loop<decltype(part)::value, mode, energy, weighted, periodic, heated>(p, range...);
          return std::size_t(0);
        });
        if (energy)
          {
            // The dilatation's share, once per point.
            const double *m     = state.fields.get("weighted_volume").begin();
            const double *gamma = state.fields.get("lps_gamma").begin();
            for (const unsigned int i : points)
              {
                // Weighted: w_i K = m_i (gamma_i + beta_i / 3) / 3 of the scaled fields.
                const double Ki = energy_weighted ? m[i] * (gamma[i] + p.beta[i] / 3) / 3 : K;
                state.energy[i] += 0.5 * Ki * p.theta[i] * p.theta[i];
              }
          }
      }

      /// The bonds [from, last) of point i, the @p part of its family, in
      /// the force and the deviatoric energy (vectorized as
      /// pair_dilatation_loop()).
      template <PairPart part, BondDamage mode, bool energy, bool weighted, bool periodic, bool heated>
      static void
      pair_force_loop(const PairData &p, const unsigned int i, const std::size_t from, const std::size_t last)
      {
        constexpr bool      masked = pair_masked(part), scatter = pair_scatters(part);
        const double       *V = p.V, *alpha = p.alpha, *beta = p.beta, *theta = p.theta, *eps_T = p.eps_T;
        double             *f = p.f, *energy_density = p.energy;
        const BondOrigin    origin(p.X, p.u, i);
        const double        Vi = V[i], ai = alpha[i], bi = beta[i], third_theta = theta[i] / 3;
        double              fx = 0, fy = 0, fz = 0, Wd = 0;
  #pragma omp simd reduction(+ : fx, fy, fz, Wd)
        for (std::size_t b = from; b < last; ++b)
          {
            const unsigned int j = p.neighbor[b];
            unsigned int       on_i, on_j;
            pair_shares<part>(masked && p.listed(j), on_i, on_j);
            double ev[3], y[3];
            bond_vectors<periodic>(p.X, p.u, j, origin, p.box, ev, y);
            const double dx = y[0], dy = y[1], dz = y[2];
            const double r0 = std::sqrt(ev[0] * ev[0] + ev[1] * ev[1] + ev[2] * ev[2]);
            const double r  = std::sqrt(dx * dx + dy * dy + dz * dz);
            const double e  = heated ? r - r0 - 0.5 * (eps_T[i] + eps_T[j]) * r0 : r - r0;
            const double w  = bond_weight<mode, weighted>(p, b);
            const double kb = w * (r0 * (ai + alpha[j]) + (bi + beta[j]) * e) / r;
            const PairSplit k = split_pair<masked>(kb, Vi, V[j], i, j, on_i, on_j);
            fx += k.on_i * dx;
            fy += k.on_i * dy;
            fz += k.on_i * dz;
            if constexpr (scatter)
              scatter_pair_force(f, k.target, k.on_j, dx, dy, dz);
            if (energy)
              {
                const double edi = e - third_theta * r0;
                Wd += on_i != 0 ? w * edi * edi * V[j] : 0.0;
                if constexpr (scatter)
                  {
                    const double edj = e - theta[j] / 3 * r0;
                    energy_density[k.target] += on_j != 0 ? 0.5 * beta[j] * w * edj * edj * Vi : 0.0;
                  }
              }
          }
        f[3 * i] += fx;
        f[3 * i + 1] += fy;
        f[3 * i + 2] += fz;
        if (energy)
          energy_density[i] += 0.5 * bi * Wd;
      }

      BondPairs pairs;
    };
  } // namespace

  PERIDEAL_REGISTER(Material, LPS, "LPS",
                    "Linear peridynamic solid, state based (Peridigm's 'Elastic'). "
                    "Keys: Density, two of Bulk modulus, Shear modulus, Young's modulus, Poisson's ratio, Thermal "
                    "expansion coefficient, Influence function, Surface correction.")
} // namespace perideal
