// Viscoelastic ordinary state-based solid (Peridigm's "Viscoelastic"):
// Mitchell, "A non-local, ordinary-state-based viscoelasticity model for
// peridynamics", SAND2011-8064. LPS (lps.cc) with omega = 1 (times beta_ij
// with partial volumes): an elastic dilatational part and a deviatoric part
// of a standard linear solid, a spring lambda_inf = 1 - lambda_i in parallel
// with a Maxwell element (spring lambda_i, back extension e^b per bond):
//   m_i = sum_j omega |xi|^2 V_j,  theta_i = (3/m_i) sum_j omega |xi| e V_j,
//   e^d = e - theta_i |xi| / 3,    alpha_i = 15 G / m_i,
//   t_ij = omega [(3K/m_i) theta_i |xi| + alpha_i (lambda_inf e^d + lambda_i (e^d - e^b))],
//   d e^b / dt = (e^d - e^b) / tau_b.
// Time integration (Mitchell's report, Peridigm's viscoelastic.cxx): e^d
// linear in time over the step dt = ModelState::dt, integrated exactly:
//   decay = exp(-dt / tau_b),  beta = 1 - tau_b (1 - decay) / dt,
//   e^b_NP1 = e^b_N decay + e^d_N (1 - decay) + beta (e^d_NP1 - e^d_N);
// dt = 0 (the initial evaluation) is the limit dt -> 0: e^b_NP1 = e^b_N.
// Under a held extension the deviatoric force relaxes as lambda_inf +
// lambda_i exp(-t / tau_b), exactly. Energy: stored W_i = K theta^2/2 +
// (alpha_i/2) sum_j omega [lambda_inf (e^d)^2 + lambda_i (e^d - e^b)^2] V_j;
// dissipated by the dashpot at the rate (alpha_i lambda_i / tau_b) sum_j omega
// (e^d - e^b)^2 V_j, integrated over the step by the trapezoid rule into the
// history D (a dissipation field: the globals' material_dissipation).
// Keys: 'Relaxation time' = Peridigm's "tau b", 'Viscous fraction' =
// "lambda_i". The force on i needs j's half, whose e^b and e^d_N of bond j->i
// live on j's owner: every bond keeps replicas, updated by the same formula
// from j's ghosted dilatation, so both copies agree bit for bit.
// Thermal strain (shared_api.md): e = |y| - |xi| - a_T (dT_i + dT_j)/2 |xi|.
// Bond damage: binary (state.broken); blocks of different horizons are
// refused. No analytic tangent: the implicit solvers use finite differences.

#include <perideal/material/material.h>

#include <cmath>
#include <limits>

namespace perideal
{
  using namespace dealii;

  class Viscoelastic : public Material
  {
  public:
    static void
    declare_parameters(ParameterHandler &prm)
    {
      prm.declare_entry("Density", "0", Patterns::Double(), "Mass density rho.");
      prm.declare_entry("Bulk modulus", "0", Patterns::Double(), "Bulk modulus K.");
      prm.declare_entry("Shear modulus", "0", Patterns::Double(),
                        "Instantaneous shear modulus G (the deviatoric response at t = 0+).");
      prm.declare_entry("Relaxation time", "1", Patterns::Double(),
                        "tau_b > 0 of the Maxwell element (Peridigm's 'tau b').");
      prm.declare_entry("Viscous fraction", "0.5", Patterns::Double(),
                        "lambda_i in [0, 1]: the share of G that relaxes; the long-time shear modulus is "
                        "(1 - lambda_i) G (Peridigm's 'lambda_i').");
      prm.declare_entry("Thermal expansion coefficient", "0", Patterns::Double(),
                        "alpha: a free bond (a free body) strains by alpha (T - T_ref)");
    }

    void
    parse_parameters(ParameterHandler &prm, const std::string &path) override
    {
      rho      = prm.get_double("Density");
      K        = prm.get_double("Bulk modulus");
      G        = prm.get_double("Shear modulus");
      tau      = prm.get_double("Relaxation time");
      lambda_i = prm.get_double("Viscous fraction");
      alpha_T  = prm.get_double("Thermal expansion coefficient");
      require_positive(rho, path + "/Density");
      require_positive(K, path + "/Bulk modulus");
      require_positive(G, path + "/Shear modulus");
      require_positive(tau, path + "/Relaxation time");
      AssertThrow(lambda_i >= 0 && lambda_i <= 1,
                  ExcMessage(path + "/Viscous fraction must be in [0, 1], got " + prm.get("Viscous fraction")));
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
      return {{"ves_weighted_volume", FieldUse::constant},
              {"ves_kappa", FieldUse::constant}, // 3K/m
              {"ves_alpha", FieldUse::constant}, // 15G/m
              {"ves_coupling", FieldUse::constant},
              {"ves_dilatation", FieldUse::stage},
              {"ves_dissipation", FieldUse::history, 1, "Viscous dissipation density", true}};
    }

    std::vector<BondField>
    bond_fields() const override
    {
      // e^d and e^b of the bond's own half, and replicas of the other end's.
      return {{"ves_ed"}, {"ves_eb"}, {"ves_ed_other"}, {"ves_eb_other"}};
    }

    void
    initialize(const ModelState &state, const std::vector<unsigned int> &points) override
    {
      AssertThrow(state.bonds.family.empty(),
                  ExcMessage(material_path + ": the Viscoelastic model does not support blocks of different "
                                             "horizons bonded to each other; give the blocks one horizon"));
      const double *V = state.cloud.volume.data();
      if (!state.bonds.volume_fraction.empty())
        omega.assign(state.bonds.volume_fraction.begin(), state.bonds.volume_fraction.end());
      VectorType &m     = state.fields.get("ves_weighted_volume");
      VectorType &kappa = state.fields.get("ves_kappa");
      VectorType &alpha = state.fields.get("ves_alpha");
      VectorType &D     = state.fields.get("ves_coupling");
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
      // LPS's Gershgorin bound (lps.cc) with the instantaneous moduli: the
      // stiffest response, the dashpot's spring unrelaxed.
      const double     *V     = state.cloud.volume.data();
      const VectorType &alpha = state.fields.get("ves_alpha");
      const VectorType &kappa = state.fields.get("ves_kappa");
      const VectorType &m     = state.fields.get("ves_weighted_volume");
      const VectorType &D     = state.fields.get("ves_coupling");
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
    double              rho = 0, K = 0, G = 0, tau = 1, lambda_i = 0.5, alpha_T = 0;
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

    /// Bond b = i->j: |xi|, |y|, the mechanical extension e; writes y.
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

    template <bool weighted, bool damaged>
    double
    weight(const ModelState &state, const std::size_t b) const
    {
      double w = weighted ? omega[b] : 1.0;
      if constexpr (damaged)
        w *= 1.0 - state.broken[b];
      return w;
    }

    template <bool weighted, bool periodic, bool damaged, bool thermal>
    void
    stage(const ModelState &state, const std::vector<unsigned int> &points) const
    {
      const double       *V        = state.cloud.volume.data();
      const std::size_t  *offsets  = state.bonds.offsets.data();
      const unsigned int *neighbor = state.bonds.neighbor.data();
      const double       *m        = state.fields.get("ves_weighted_volume").begin();
      double             *theta    = state.fields.get("ves_dilatation").begin();
      for (const unsigned int i : points)
        {
          const BondOrigin origin(state.cloud.X.data(), state.u, i);
          double           sum = 0;
          for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
            {
              double y[3], r0, r, e;
              bond<periodic, thermal>(state, origin, i, neighbor[b], alpha_T, y, r0, r, e);
              sum += weight<weighted, damaged>(state, b) * r0 * e * V[neighbor[b]];
            }
          theta[i] = m[i] > 0 ? 3 * sum / m[i] : 0.0;
        }
    }

    template <bool weighted, bool periodic, bool damaged, bool thermal, bool energy>
    void
    force(const ModelState &state, const std::vector<unsigned int> &points) const
    {
      const double       *V        = state.cloud.volume.data();
      const std::size_t  *offsets  = state.bonds.offsets.data();
      const unsigned int *neighbor = state.bonds.neighbor.data();
      const double       *kappa    = state.fields.get("ves_kappa").begin();
      const double       *alpha    = state.fields.get("ves_alpha").begin();
      const double       *theta    = state.fields.get("ves_dilatation").begin();
      const double       *D_N      = state.fields.old("ves_dissipation").begin();
      double             *Dv       = state.fields.get("ves_dissipation").begin();
      const double       *ed_N     = state.fields.bond_old("ves_ed");
      const double       *eb_N     = state.fields.bond_old("ves_eb");
      const double       *edo_N    = state.fields.bond_old("ves_ed_other");
      const double       *ebo_N    = state.fields.bond_old("ves_eb_other");
      double             *ed_NP1   = state.fields.bond("ves_ed");
      double             *eb_NP1   = state.fields.bond("ves_eb");
      double             *edo_NP1  = state.fields.bond("ves_ed_other");
      double             *ebo_NP1  = state.fields.bond("ves_eb_other");
      double             *f        = state.force;
      // The step's exact integration weights; dt = 0: the limit, e^b frozen.
      const double dt     = state.dt;
      const double decay  = dt > 0 ? std::exp(-dt / tau) : 1.0;
      const double beta   = dt > 0 ? 1 - tau * (1 - decay) / dt : 0.0;
      const double l_inf  = 1 - lambda_i;
      for (const unsigned int i : points)
        {
          const BondOrigin origin(state.cloud.X.data(), state.u, i);
          const double     ti = theta[i], ki = kappa[i] * ti, ai = alpha[i];
          double           fx = 0, fy = 0, fz = 0, Wd = 0, rate_N = 0, rate = 0;
          for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
            {
              const unsigned int j = neighbor[b];
              double             y[3], r0, r, e;
              bond<periodic, thermal>(state, origin, i, j, alpha_T, y, r0, r, e);
              const double edi = e - ti * r0 / 3;
              const double edj = e - theta[j] * r0 / 3;
              const double ebi = eb_N[b] * decay + ed_N[b] * (1 - decay) + beta * (edi - ed_N[b]);
              const double ebj = ebo_N[b] * decay + edo_N[b] * (1 - decay) + beta * (edj - edo_N[b]);
              ed_NP1[b]        = edi;
              eb_NP1[b]        = ebi;
              edo_NP1[b]       = edj;
              ebo_NP1[b]       = ebj;
              const double w   = weight<weighted, damaged>(state, b);
              const double t   = w * (r0 * (ki + kappa[j] * theta[j]) + ai * (edi - lambda_i * ebi) +
                                    alpha[j] * (edj - lambda_i * ebj));
              const double k   = t * V[j] / r;
              fx += k * y[0];
              fy += k * y[1];
              fz += k * y[2];
              const double v_N = ed_N[b] - eb_N[b], v = edi - ebi;
              rate_N += w * v_N * v_N * V[j];
              rate += w * v * v * V[j];
              if (energy)
                Wd += w * (l_inf * edi * edi + lambda_i * v * v) * V[j];
            }
          f[3 * i] += fx;
          f[3 * i + 1] += fy;
          f[3 * i + 2] += fz;
          Dv[i] = D_N[i] + 0.5 * dt * ai * lambda_i / tau * (rate_N + rate);
          if (energy)
            state.energy[i] += 0.5 * K * ti * ti + 0.5 * ai * Wd;
        }
    }
  };

  PERIDEAL_REGISTER(Material, Viscoelastic, "Viscoelastic",
                    "Mitchell's ordinary state-based viscoelastic solid: LPS (omega = 1) with an elastic "
                    "dilatation and a standard-linear-solid deviatoric part (Peridigm's 'Viscoelastic'). "
                    "Keys: Density, Bulk modulus, Shear modulus, Relaxation time, Viscous fraction, Thermal "
                    "expansion coefficient.")
} // namespace perideal
