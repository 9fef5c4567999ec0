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
// the equivalent plastic strain eps_p = sqrt(m/5) ||e^dp|| for a homogeneous
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
// Thermal strain (shared_api.md): e = |y| - |xi| - a_T (dT_i + dT_j)/2 |xi|.
// Bond damage: binary (state.broken; a broken bond keeps its e^dp); no
// continuous damage. Blocks of different horizons are refused. The analytic
// tangent is not provided: the implicit solvers use finite differences.

#include <perideal/material/material.h>

#include <cmath>
#include <limits>

namespace perideal
{
  using namespace dealii;

  class ElasticPlastic : public Material
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry("Density", "0", Patterns::Double(), "Mass density rho.");
      prm.declare_entry("Bulk modulus", "0", Patterns::Double(), "Bulk modulus K.");
      prm.declare_entry("Shear modulus", "0", Patterns::Double(), "Shear modulus G.");
      prm.declare_entry("Yield stress", "0", Patterns::Double(),
                        "Initial von Mises yield stress Y0 > 0 (Peridigm's 'Yield Stress').");
      prm.declare_entry("Hardening modulus", "0", Patterns::Double(),
                        "Linear isotropic hardening H >= 0: Y = Y0 + H eps_p, eps_p the equivalent plastic "
                        "strain (uniaxial stress: tangent modulus E H / (E + H)); 0: perfectly plastic "
                        "(Peridigm's 'Hardening Modulus' of 'Elastic Plastic Hardening').");
      prm.declare_entry("Thermal expansion coefficient", "0", Patterns::Double(),
                        "alpha: a free bond (a free body) strains by alpha (T - T_ref)");
    }

    void
    parse_parameters(ParameterHandler &prm, const std::string &path) override
    {
      rho     = prm.get_double("Density");
      K       = prm.get_double("Bulk modulus");
      G       = prm.get_double("Shear modulus");
      Y0      = prm.get_double("Yield stress");
      H       = prm.get_double("Hardening modulus");
      alpha_T = prm.get_double("Thermal expansion coefficient");
      require_positive(rho, path + "/Density");
      require_positive(K, path + "/Bulk modulus");
      require_positive(G, path + "/Shear modulus");
      require_positive(Y0, path + "/Yield stress");
      AssertThrow(H >= 0 && std::isfinite(H),
                  ExcMessage(path + "/Hardening modulus must be >= 0 (0: perfectly plastic), got " +
                             prm.get("Hardening modulus")));
      AssertThrow(std::isfinite(alpha_T), ExcMessage(path + "/Thermal expansion coefficient must be finite"));
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
    shear_modulus() const override
    {
      return G;
    }

    std::vector<PointField>
    point_fields() const override
    {
      return {{"eps_weighted_volume", FieldUse::constant},
              {"eps_kappa", FieldUse::constant}, // 3K/m
              {"eps_alpha", FieldUse::constant}, // 15G/m
              {"eps_coupling", FieldUse::constant},
              {"eps_dilatation", FieldUse::stage},
              {"eps_scale", FieldUse::stage}, // the return factor s
              {"eps_plastic_strain", FieldUse::history, 1, "Equivalent plastic strain"},
              {"eps_dissipation", FieldUse::history, 1, "Plastic dissipation density", true}};
    }

    std::vector<BondField>
    bond_fields() const override
    {
      return {{"eps_edp"}, {"eps_edp_other"}};
    }

    void
    initialize(const ModelState &state, const std::vector<unsigned int> &points) override
    {
      AssertThrow(state.bonds.family.empty(),
                  ExcMessage(material_path + ": the Elastic plastic model does not support blocks of different "
                                             "horizons bonded to each other; give the blocks one horizon"));
      const double *V = state.cloud.volume.data();
      if (!state.bonds.volume_fraction.empty())
        omega.assign(state.bonds.volume_fraction.begin(), state.bonds.volume_fraction.end());
      VectorType &m     = state.fields.get("eps_weighted_volume");
      VectorType &kappa = state.fields.get("eps_kappa");
      VectorType &alpha = state.fields.get("eps_alpha");
      VectorType &D     = state.fields.get("eps_coupling");
      for (const unsigned int i : points)
        {
          double mi = 0, Ai = 0;
          for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
            {
              const unsigned int j  = state.bonds.neighbor[b];
              const double       r0 = state.cloud.bond_vector(i, j).norm();
              const double       w  = omega.empty() ? 1.0 : omega[b];
              mi += w * r0 * r0 * V[j];
              Ai += w * r0 * V[j];
            }
          const double inverse   = mi > 0 ? 1 / mi : 0.0;
          m.local_element(i)     = mi;
          kappa.local_element(i) = 3 * K * inverse;
          alpha.local_element(i) = 15 * G * inverse;
          D.local_element(i)     = std::abs(3 * K - 5 * G) * inverse * Ai * inverse;
        }
    }

    void
    compute_stage(const ModelState &state, const std::vector<unsigned int> &points) const override
    {
      variants(state, [&](auto W, auto P, auto D, auto T) {
        stage<decltype(W)::value, decltype(P)::value, decltype(D)::value, decltype(T)::value>(state, points);
      });
    }

    void
    compute_force(const ModelState &state, const std::vector<unsigned int> &points) const override
    {
      variants(state, [&](auto W, auto P, auto D, auto T) {
        constexpr bool w = decltype(W)::value, p = decltype(P)::value, d = decltype(D)::value,
                       t = decltype(T)::value;
        if (state.energy)
          force<w, p, d, t, true>(state, points);
        else
          force<w, p, d, t, false>(state, points);
      });
    }

    double
    stable_time_step(const ModelState &state, const std::vector<unsigned int> &points) const override
    {
      // LPS's Gershgorin bound of the elastic tangent (lps.cc, beta = alpha,
      // gamma = kappa - alpha/3): plastic flow only softens the response.
      const double     *V     = state.cloud.volume.data();
      const VectorType &alpha = state.fields.get("eps_alpha");
      const VectorType &kappa = state.fields.get("eps_kappa");
      const VectorType &m     = state.fields.get("eps_weighted_volume");
      const VectorType &D     = state.fields.get("eps_coupling");
      double            dt    = std::numeric_limits<double>::max();
      for (const unsigned int i : points)
        {
          double pair = 0, Ai = 0, neighbors = 0;
          for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
            {
              const unsigned int j  = state.bonds.neighbor[b];
              const double       r0 = state.cloud.bond_vector(i, j).norm();
              const double       w  = omega.empty() ? 1.0 : omega[b];
              pair += (alpha.local_element(i) + alpha.local_element(j)) * w * V[j];
              Ai += w * r0 * V[j];
              neighbors += w * r0 * V[j] * D.local_element(j);
            }
          if (m.local_element(i) == 0)
            continue;
          const double gamma  = kappa.local_element(i) - alpha.local_element(i) / 3;
          const double lambda = (2 * pair + 6 * std::abs(gamma) * Ai * Ai / m.local_element(i) + 6 * neighbors) / rho;
          if (lambda > 0)
            dt = std::min(dt, 2 / std::sqrt(lambda));
        }
      return dt;
    }

  private:
    double              rho = 0, K = 0, G = 0, Y0 = 0, H = 0, alpha_T = 0;
    std::string         material_path;
    std::vector<double> omega; // beta_ij per bond, only with partial volumes

    /// Calls @p f with the compile-time variants of this state: per-bond
    /// weights (partial volumes), periodic, binary damage, thermal strain.
    template <typename F>
    void
    variants(const ModelState &state, const F &f) const
    {
      with_flag(!omega.empty(), [&](auto W) {
        with_flag(state.cloud.periodicity.any(), [&](auto P) {
          with_flag(state.broken != nullptr, [&](auto D) {
            with_flag(state.temperature_change != nullptr && alpha_T != 0,
                      [&](auto T) { f(W, P, D, T); });
          });
        });
      });
    }

    /// Bond b = i->j: {|xi|, |y|, the mechanical extension e}; writes y.
    template <bool periodic, bool thermal>
    static void
    bond(const ModelState &state, const BondOrigin &origin, const unsigned int i, const unsigned int j,
         const double alpha_T, double (&y)[3], double &r0, double &r, double &e)
    {
      double ev[3];
      bond_vectors<periodic>(state.cloud.X.data(), state.u, j, origin, state.cloud.periodicity, ev, y);
      r0 = std::sqrt(ev[0] * ev[0] + ev[1] * ev[1] + ev[2] * ev[2]);
      r  = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
      e  = r - r0;
      if constexpr (thermal)
        e -= alpha_T * (0.5 * (state.temperature_change[i] + state.temperature_change[j])) * r0;
    }

    /// The dilatation, the return factor s and the point history of each point.
    template <bool weighted, bool periodic, bool damaged, bool thermal>
    void
    stage(const ModelState &state, const std::vector<unsigned int> &points) const
    {
      const double       *V        = state.cloud.volume.data();
      const std::size_t  *offsets  = state.bonds.offsets.data();
      const unsigned int *neighbor = state.bonds.neighbor.data();
      const double       *m        = state.fields.get("eps_weighted_volume").begin();
      const double       *alpha    = state.fields.get("eps_alpha").begin();
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
          if (m[i] == 0)
            continue;
          const BondOrigin origin(state.cloud.X.data(), state.u, i);
          double           sum = 0;
          for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
            {
              double y[3], r0, r, e;
              bond<periodic, thermal>(state, origin, i, neighbor[b], alpha_T, y, r0, r, e);
              sum += weight<weighted, damaged>(state, b) * r0 * e * V[neighbor[b]];
            }
          const double th = 3 * sum / m[i];
          double       norm2 = 0; // ||e^d - e^dp_N||^2
          for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
            {
              double y[3], r0, r, e;
              bond<periodic, thermal>(state, origin, i, neighbor[b], alpha_T, y, r0, r, e);
              const double ed = e - th * r0 / 3 - edp_N[b];
              norm2 += weight<weighted, damaged>(state, b) * ed * ed * V[neighbor[b]];
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
    }

    template <bool weighted, bool damaged>
    double
    weight(const ModelState &state, const std::size_t b) const
    {
      double w = weighted ? omega[b] : 1.0;
      if constexpr (damaged)
        w *= 1.0 - state.broken[b];
      return w;
    }

    template <bool weighted, bool periodic, bool damaged, bool thermal, bool energy>
    void
    force(const ModelState &state, const std::vector<unsigned int> &points) const
    {
      const double       *V         = state.cloud.volume.data();
      const std::size_t  *offsets   = state.bonds.offsets.data();
      const unsigned int *neighbor  = state.bonds.neighbor.data();
      const double       *kappa     = state.fields.get("eps_kappa").begin();
      const double       *alpha     = state.fields.get("eps_alpha").begin();
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
              bond<periodic, thermal>(state, origin, i, j, alpha_T, y, r0, r, e);
              // A broken bond keeps its plastic extensions.
              const double keep = damaged ? 1.0 - state.broken[b] : 1.0;
              const double edi  = e - ti * r0 / 3;
              const double edj  = e - theta[j] * r0 / 3;
              const double pi   = edp_N[b] + keep * ci * (edi - edp_N[b]);
              const double pj   = other_N[b] + keep * (1 - scale[j]) * (edj - other_N[b]);
              edp[b]            = pi;
              other[b]          = pj;
              const double w    = weight<weighted, damaged>(state, b);
              const double t    = w * (r0 * (ki + kappa[j] * theta[j]) + ai * (edi - pi) + alpha[j] * (edj - pj));
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

  PERIDEAL_REGISTER(Material, ElasticPlastic, "Elastic plastic",
                    "Mitchell's ordinary state-based elastic-plastic solid: LPS (omega = 1) with a von Mises "
                    "yield of the deviatoric force state, radial return, linear isotropic hardening "
                    "(Peridigm's 'Elastic Plastic' and 'Elastic Plastic Hardening'). Keys: Density, Bulk "
                    "modulus, Shear modulus, Yield stress, Hardening modulus, Thermal expansion coefficient.")
} // namespace perideal
