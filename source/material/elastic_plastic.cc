// Elastic-plastic ordinary state-based solid (Peridigm's "Elastic Plastic" and
// "Elastic Plastic Hardening"): Mitchell, "A nonlocal, ordinary, state-based
// plasticity model for peridynamics", SAND2011-3166. LPS (lps.cc) with
// omega = 1 (times beta_ij with partial volumes) and a plastic part of the
// deviatoric extension, e^d = e^de + e^dp:
//   m_i = sum_j omega |xi|^2 V_j,  theta_i = (3/m_i) sum_j omega |xi| e V_j,
//   e^d = e - theta_i |xi| / 3,    t_ij = omega [(3K/m_i) theta_i |xi| + t^d],
//   t^d = alpha_i (e^d - e^dp),    alpha_i = 15 G / m_i.
// Yield: f = ||t^d||^2 / 2 - psi0 <= 0, ||t^d||^2 = sum_j omega (t^d)^2 V_j,
// psi0 = 5 Y^2 / (2 m_i). For the continuum ball m = 4 pi delta^5 / 5, so psi0
// = 25 Y^2 / (8 pi delta^5), Mitchell's and Peridigm's constant; with the
// point's own m_i the yield is reached at the von Mises stress Y of the
// family's own sums (also where a surface cuts it). In stress terms, q =
// sqrt(m_i/5) ||t^d|| is the von Mises stress of a homogeneous deformation.
// Linear isotropic hardening Y = Y0 + H eps_p (H = 0: perfectly plastic), with
// the equivalent plastic strain eps_p = sqrt(5/m) ||e^dp|| for a homogeneous
// plastic flow (the continuum's sqrt(2/3 eps^p:eps^p)). Radial return from the
// trial state t_tr = alpha (e^d - e^dp_N) (backward Euler, as J2 plasticity):
//   q_tr = sqrt(m_i/5) ||t_tr||;  if q_tr > Y_N = Y0 + H eps_p,N:
//   a = (q_tr - Y_N) / (3G + H),  s = (Y_N + H a) / q_tr,  t^d = s t_tr,
//   e^dp_NP1 = e^dp_N + (1 - s) (e^d - e^dp_N),  eps_p,NP1 = eps_p,N + a,
// else s = 1. Dissipation density (plastic work, all of it dissipated: the
// free energy has no hardening term): D_NP1 = D_N + (Y_N + H a / 2) a, the
// integral of Y d eps_p over the step (= sum_j t^d (e^dp_NP1 - e^dp_N) V_j for
// the backward-Euler t^d when H = 0).
// Energy density (stored): W_i = K theta_i^2/2 + (alpha_i/2) sum_j omega
// (e^d - e^dp)^2 V_j. The force on i needs j's half t_ji, i.e. j's plastic
// extension of bond j->i, which lives on j's owner: every bond also keeps a
// replica of the other end's e^dp, updated by the same formula from j's
// ghosted dilatation and return factor s_j, so both copies agree bit for bit.
// Thermal strain: e = |y| - |xi| - (eps_T,i + eps_T,j)/2 |xi| (ordinary_state.h).
// Bond damage: binary (state.broken; a broken bond keeps its e^dp), a
// critical stretch applied in stage()'s first bond pass
// (fuses_stretch_criterion()); no continuous damage. Critical energy: the
// bond work of ordinary_state.h (stored and dissipated). Blocks of different horizons are refused. Tangent: the
// consistent tangent of the radial return (add_tangent()), so Newton converges
// quadratically through yield.

#include <perideal/material/elastic_constants.h>
#include <perideal/material/ordinary_state.h>

#include <cmath>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class ElasticPlastic : public OrdinaryStateMaterial
    {
    public:
      ElasticPlastic()
        : OrdinaryStateMaterial("eps_")
      {}

      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Density", "0", Patterns::Double(), "Mass density rho.");
        declare_elastic_constants(prm);
        prm.declare_entry("Yield stress", "0", Patterns::Double(),
                          "Initial von Mises yield stress Y0 > 0 (Peridigm's 'Yield Stress').");
        prm.declare_entry("Hardening modulus", "0", Patterns::Double(),
                          "Linear isotropic hardening H >= 0: Y = Y0 + H eps_p, eps_p the equivalent plastic "
                          "strain (uniaxial stress: tangent modulus E H / (E + H)); 0: perfectly plastic "
                          "(Peridigm's 'Hardening Modulus' of 'Elastic Plastic Hardening').");
        declare_thermal_expansion(prm);
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path) override
      {
        rho = prm.get_double("Density");
        require_positive(rho, path + "/Density");
        const ElasticConstants moduli = parse_elastic_constants(prm, path);
        K                             = moduli.K;
        G                             = moduli.G;
        Y0                            = prm.get_double("Yield stress");
        H                             = prm.get_double("Hardening modulus");
        alpha_T                       = parse_thermal_expansion(prm, path);
        require_positive(Y0, path + "/Yield stress");
        AssertThrow(H >= 0 && std::isfinite(H),
                    ExcMessage(path + "/Hardening modulus must be >= 0 (0: perfectly plastic), got " +
                               prm.get("Hardening modulus")));
        material_path = path;
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
        return alpha_T;
      }
      double
      shear_modulus() const override
      {
        return G;
      }

      std::vector<PointField>
      point_fields() const override
      {
        std::vector<PointField> fields = family.constant_fields();
        fields.insert(fields.end(),
                      {{"eps_dilatation", FieldUse::stage},
                       {"eps_scale", FieldUse::stage}, // the return factor s
                       {"eps_plastic_strain", FieldUse::history, 1, "Equivalent plastic strain"},
                       {"eps_dissipation", FieldUse::history, 1, "Plastic dissipation density", true}});
        return fields;
      }

      std::vector<BondField>
      bond_fields() const override
      {
        // Rewritten whole at every evaluation (force()): commit() swaps N and NP1.
        return with_work_fields({{"eps_edp", true}, {"eps_edp_other", true}});
      }

      void
      initialize(const ModelState &state, const std::vector<unsigned int> &points) override
      {
        family.initialize(state, points, K, G, material_path, "Elastic plastic");
      }

      void
      compute_stage(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        OrdinaryState::stage_variants(state, [&](auto W, auto P, auto D, auto T, auto B) {
          stage<decltype(W)::value, decltype(P)::value, decltype(D)::value, decltype(T)::value, decltype(B)::value>(
            state, points);
        });
      }

      void
      compute_force(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        force_variants(state, [&](auto W, auto P, auto D, auto T, auto B) {
          constexpr bool w = decltype(W)::value, p = decltype(P)::value, d = decltype(D)::value,
                         t = decltype(T)::value, b = decltype(B)::value;
          if (state.energy)
            force<w, p, d, t, true, b>(state, points);
          else
            force<w, p, d, t, false, b>(state, points);
        });
      }

      /// On an intact bond force()'s e^d - e^dp is s (e^d - e^dp_N), s the
      /// return factor, so W_i = K theta^2 / 2 + alpha / 2 s^2 n with n =
      /// sum w (e - theta |xi| / 3 - e^dp_N)^2 V_j, stage()'s trial norm:
      /// one pass over the bonds gives both damage states' theta and n (as
      /// sums of w |xi| e, w |xi|^2, w |xi| x and w x^2, x = e - e^dp_N),
      /// their return and their energy; nothing is written.
      double
      released_energy(const ModelState &before, const ModelState &now, const std::vector<unsigned int> &points) const override
      {
        const double *m     = now.fields.get(family.weighted_volume).begin();
        const double *alpha = now.fields.get(family.alpha).begin();
        const double *edp_N = now.fields.bond_old("eps_edp");
        const double *ep_N  = now.fields.old("eps_plastic_strain").begin();
        // sums: A = sum w |xi| e, D = sum w |xi|^2, P = sum w |xi| x, Q = sum w x^2.
        return family.released_energy<4>(
          before, now, points,
          [&](const std::size_t b, const double r0, const double e, const double w, double *s) {
            const double x = e - edp_N[b];
            s[0] += w * r0 * e;
            s[1] += w * r0 * r0;
            s[2] += w * r0 * x;
            s[3] += w * x * x;
          },
          [&](const unsigned int i, const double *s) {
            const double th   = 3 * s[0] / m[i];
            const double n    = std::max(s[3] - 2 * th * s[2] / 3 + th * th * s[1] / 9, 0.0);
            const double q_tr = std::sqrt(m[i] / 5 * n) * alpha[i];
            const double Y_N  = Y0 + H * ep_N[i];
            double       r    = 1; // the return factor
            if (q_tr > Y_N)
              r = (Y_N + H * (q_tr - Y_N) / (3 * G + H)) / q_tr;
            return 0.5 * K * th * th + 0.5 * alpha[i] * r * r * n;
          });
      }

      bool
      fuses_stretch_criterion() const override
      {
        return true; // in stage()
      }

      double
      stable_time_step(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        // The elastic bound: plastic flow only softens the response.
        return family.stable_time_step(state, points, rho);
      }

      bool
      add_tangent(const ModelState &state, const std::vector<unsigned int> &points, TangentRows &rows) const override
      {
        // The consistent tangent of the radial return (ordinary_state.h): the
        // deviatoric half is D_i(b) = alpha_i s_i eps_b, eps = e^d - e^dp_N,
        // s_i = (3G Y_N / q + H) / (3G + H) on a yielding point (1 otherwise),
        // q = alpha_i sqrt(m_i/5) n_i, n_i^2 = sum_c w eps_c^2 V_c, so
        //   dD_i(b) = alpha_i s_i d eps_b + eta_i eps_b sum_c w eps_c V_c d eps_c,
        //   eta_i = alpha_i^2 sqrt(m_i/5) (ds/dq) / n_i,  ds/dq = -3G Y_N / ((3G + H) q^2).
        const double       *V      = state.cloud.volume.data();
        const double       *m      = state.fields.get(family.weighted_volume).begin();
        const double       *kappa  = state.fields.get(family.kappa).begin();
        const double       *alpha  = state.fields.get(family.alpha).begin();
        const double       *theta  = state.fields.get("eps_dilatation").begin();
        const double       *scale  = state.fields.get("eps_scale").begin();
        const double       *ep_N   = state.fields.old("eps_plastic_strain").begin();
        const double       *edp_N  = state.fields.bond_old("eps_edp");
        const double       *oth_N  = state.fields.bond_old("eps_edp_other");
        const unsigned int  n_local = state.cloud.n_local();
        std::vector<double> deviatoric(n_local), eta(n_local, 0.0);
        for (unsigned int i = 0; i < n_local; ++i)
          deviatoric[i] = alpha[i] * scale[i];
        for (const unsigned int i : points)
          {
            if (scale[i] == 1 || m[i] == 0)
              continue;
            double norm2 = 0; // as stage()
            for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
              {
                const unsigned int j = state.bonds.neighbor[b];
                double             xi[3], y[3];
                const auto [r0, r]   = bond_geometry(state.cloud, state.u, i, j, xi, y);
                const double e       = r - r0 - OrdinaryState::thermal_extension(state, i, j, r0);
                const double eps     = e - theta[i] * r0 / 3 - edp_N[b];
                norm2 += OrdinaryState::bond_weight(state, b) * eps * eps * V[j];
              }
            const double n     = std::sqrt(norm2);
            const double q     = std::sqrt(m[i] / 5) * n * alpha[i];
            const double Y_N   = Y0 + H * ep_N[i];
            const double ds_dq = -3 * G * Y_N / ((3 * G + H) * q * q);
            eta[i]             = alpha[i] * alpha[i] * std::sqrt(m[i] / 5) * ds_dq / n;
          }
        family.add_tangent(state, points, rows, theta, deviatoric.data(), eta.data(), edp_N,
                           [&](const unsigned int i, const std::size_t b, const unsigned int j, const double e,
                               const double r0) {
                             return OrdinaryState::bond_weight(state, b) * (r0 * (kappa[i] * theta[i] + kappa[j] * theta[j]) +
                                         deviatoric[i] * (e - theta[i] * r0 / 3 - edp_N[b]) +
                                         deviatoric[j] * (e - theta[j] * r0 / 3 - oth_N[b]));
                           });
        return true;
      }

    private:
      double              rho = 0, K = 0, G = 0, Y0 = 0, H = 0, alpha_T = 0;
      std::string         material_path;

      /// The dilatation, the return factor s and the point history of each
      /// point; with @p breaking, first the fused critical stretch.
      template <bool weighted, bool periodic, bool damaged, bool thermal, bool breaking>
      void
      stage(const ModelState &state, const std::vector<unsigned int> &points) const
      {
        std::size_t         newly_broken = 0;
        const double       *V        = state.cloud.volume.data();
        const std::size_t  *offsets  = state.bonds.offsets.data();
        const unsigned int *neighbor = state.bonds.neighbor.data();
        const double       *m        = state.fields.get(family.weighted_volume).begin();
        const double       *alpha    = state.fields.get(family.alpha).begin();
        const double       *edp_N    = state.fields.bond_old("eps_edp");
        const double       *ep_N     = state.fields.old("eps_plastic_strain").begin();
        const double       *D_N      = state.fields.old("eps_dissipation").begin();
        double             *theta    = state.fields.get("eps_dilatation").begin();
        double             *scale    = state.fields.get("eps_scale").begin();
        double             *ep       = state.fields.get("eps_plastic_strain").begin();
        double             *Dp       = state.fields.get("eps_dissipation").begin();
        for (const unsigned int i : points)
          {
            ep[i]    = ep_N[i];
            Dp[i]    = D_N[i];
            scale[i] = 1;
            theta[i] = 0;
            const BondOrigin origin(state.cloud.X.data(), state.u, i);
            double           sum = 0;
            for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
              {
                if constexpr (breaking)
                  newly_broken += OrdinaryState::break_bond<periodic>(state, origin, neighbor[b], b);
                double y[3], r0, r, e;
                OrdinaryState::bond<periodic, thermal>(state, origin, i, neighbor[b], y, r0, r, e);
                sum += OrdinaryState::weight<weighted, damaged>(state, b) * r0 * e * V[neighbor[b]];
              }
            if (m[i] == 0)
              continue;
            const double th = 3 * sum / m[i];
            double       norm2 = 0; // ||e^d - e^dp_N||^2
            for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
              {
                double y[3], r0, r, e;
                OrdinaryState::bond<periodic, thermal>(state, origin, i, neighbor[b], y, r0, r, e);
                const double ed = e - th * r0 / 3 - edp_N[b];
                norm2 += OrdinaryState::weight<weighted, damaged>(state, b) * ed * ed * V[neighbor[b]];
              }
            theta[i]          = th;
            const double q_tr = std::sqrt(m[i] / 5 * norm2) * alpha[i];
            const double Y_N  = Y0 + H * ep_N[i];
            if (q_tr > Y_N)
              {
                const double a = (q_tr - Y_N) / (3 * G + H);
                scale[i]       = (Y_N + H * a) / q_tr;
                ep[i]          = ep_N[i] + a;
                Dp[i]          = D_N[i] + (Y_N + 0.5 * H * a) * a;
              }
          }
        if constexpr (breaking)
          state.breaking->newly_broken += newly_broken;
      }

      template <bool weighted, bool periodic, bool damaged, bool thermal, bool energy, bool bond_work>
      void
      force(const ModelState &state, const std::vector<unsigned int> &points) const
      {
        const auto work_update = bond_work ? OrdinaryState::WorkUpdate(state, family) : OrdinaryState::WorkUpdate();
        const double       *V         = state.cloud.volume.data();
        const std::size_t  *offsets   = state.bonds.offsets.data();
        const unsigned int *neighbor  = state.bonds.neighbor.data();
        const double       *kappa     = state.fields.get(family.kappa).begin();
        const double       *alpha     = state.fields.get(family.alpha).begin();
        const double       *theta     = state.fields.get("eps_dilatation").begin();
        const double       *scale     = state.fields.get("eps_scale").begin();
        const double       *edp_N     = state.fields.bond_old("eps_edp");
        const double       *other_N   = state.fields.bond_old("eps_edp_other");
        double             *edp       = state.fields.bond("eps_edp");
        double             *other     = state.fields.bond("eps_edp_other");
        double             *f         = state.force;
        for (const unsigned int i : points)
          {
            const BondOrigin origin(state.cloud.X.data(), state.u, i);
            const double     ti = theta[i], ki = kappa[i] * ti, ai = alpha[i], ci = 1 - scale[i];
            double           fx = 0, fy = 0, fz = 0, Wd = 0;
            for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
              {
                const unsigned int j = neighbor[b];
                double             y[3], r0, r, e;
                OrdinaryState::bond<periodic, thermal>(state, origin, i, j, y, r0, r, e);
                // A broken bond keeps its plastic extensions.
                const double keep = damaged ? 1.0 - state.broken[b] : 1.0;
                const double edi  = e - ti * r0 / 3;
                const double edj  = e - theta[j] * r0 / 3;
                const double pi   = edp_N[b] + keep * ci * (edi - edp_N[b]);
                const double pj   = other_N[b] + keep * (1 - scale[j]) * (edj - other_N[b]);
                edp[b]            = pi;
                other[b]          = pj;
                const double w    = OrdinaryState::weight<weighted, damaged>(state, b);
                const double t    = w * (r0 * (ki + kappa[j] * theta[j]) + ai * (edi - pi) + alpha[j] * (edj - pj));
                // t again, with the two ends' terms added alike on both owners.
                if constexpr (bond_work)
                  work_update.add(b,
                                  w * (r0 * OrdinaryState::symmetric_sum(ki, kappa[j] * theta[j]) +
                                       OrdinaryState::symmetric_sum(ai * (edi - pi), alpha[j] * (edj - pj))),
                                  e);
                const double k    = t * V[j] / r;
                fx += k * y[0];
                fy += k * y[1];
                fz += k * y[2];
                if (energy)
                  Wd += w * (edi - pi) * (edi - pi) * V[j];
              }
            f[3 * i] += fx;
            f[3 * i + 1] += fy;
            f[3 * i + 2] += fz;
            if (energy)
              state.energy[i] += 0.5 * K * ti * ti + 0.5 * ai * Wd;
          }
      }
    };
  } // namespace

  PERIDEAL_REGISTER(Material, ElasticPlastic, "Elastic plastic",
                    "Mitchell's ordinary state-based elastic-plastic solid: LPS (omega = 1) with a von Mises "
                    "yield of the deviatoric force state, radial return, linear isotropic hardening "
                    "(Peridigm's 'Elastic Plastic' and 'Elastic Plastic Hardening'). Keys: Density, two of "
                    "Bulk modulus, Shear modulus, Young's modulus, Poisson's ratio, Yield stress, Hardening modulus, Thermal expansion coefficient.")
} // namespace perideal
