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
// (e^d - e^b)^2 V_j, integrated over the step exactly for the same e^d linear
// in time into the history D (a dissipation field: the globals'
// material_dissipation): with v = e^d - e^b, v_N its value at the step's
// start, Delta = e^d_NP1 - e^d_N and a = dt / tau_b,
//   (1/tau_b) int v^2 dt = v_N^2 (1 - decay^2)/2 + v_N Delta (1 - decay)^2 / a
//                          + Delta^2 g(a) / a^2,
//   g(a) = a - 2 (1 - e^-a) + (1 - e^-2a)/2   (a^3/3 - a^4/4 + ... for small a).
// It stays bounded for tau_b far below dt (the dashpot relaxes v_N within the
// step: v_N^2 / 2), where the trapezoid rule's dt/tau_b v_N^2 / 2 overflowed
// (Relaxation time = 1e-300 gave a dissipation of 1.9e258).
// Keys: 'Relaxation time' = Peridigm's "tau b", 'Viscous fraction' =
// "lambda_i". The force on i needs j's half, whose e^b and e^d_N of bond j->i
// live on j's owner: every bond keeps replicas, updated by the same formula
// from j's ghosted dilatation, so both copies agree bit for bit.
// Thermal strain: e = |y| - |xi| - (eps_T,i + eps_T,j)/2 |xi| (ordinary_state.h).
// Bond damage: binary (state.broken); a critical stretch runs in stage()'s
// first bond pass (fuses_stretch_criterion()). Critical energy: the bond work
// of ordinary_state.h (stored and dissipated by the dashpots). Blocks of different horizons are
// refused. Tangent: analytic (add_tangent(); LPS's with the step's relaxed
// deviatoric modulus), so Newton converges quadratically.

#include <perideal/material/elastic_constants.h>
#include <perideal/material/ordinary_state.h>

#include <cmath>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class Viscoelastic : public OrdinaryStateMaterial
    {
    public:
      Viscoelastic()
        : OrdinaryStateMaterial("ves_")
      {}

      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Density", "0", Patterns::Double(), "Mass density rho.");
        declare_elastic_constants(prm); // G, E, nu: the instantaneous ones (t = 0+)
        prm.declare_entry("Relaxation time", "1", Patterns::Double(),
                          "tau_b > 0 of the Maxwell element (Peridigm's 'tau b').");
        prm.declare_entry("Viscous fraction", "0.5", Patterns::Double(),
                          "lambda_i in [0, 1]: the share of G that relaxes; the long-time shear modulus is "
                          "(1 - lambda_i) G (Peridigm's 'lambda_i').");
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
        tau                           = prm.get_double("Relaxation time");
        lambda_i                      = prm.get_double("Viscous fraction");
        alpha_T                       = parse_thermal_expansion(prm, path);
        require_positive(tau, path + "/Relaxation time");
        AssertThrow(lambda_i >= 0 && lambda_i <= 1,
                    ExcMessage(path + "/Viscous fraction must be in [0, 1], got " + prm.get("Viscous fraction")));
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
                      {{"ves_dilatation", FieldUse::stage},
                       {"ves_dissipation", FieldUse::history, 1, "Viscous dissipation density", true}});
        return fields;
      }

      std::vector<BondField>
      bond_fields() const override
      {
        // e^d and e^b of the bond's own half, and replicas of the other end's; rewritten
        // whole at every evaluation (force()): commit() swaps N and NP1.
        return with_work_fields({{"ves_ed", true}, {"ves_eb", true}, {"ves_ed_other", true}, {"ves_eb_other", true}});
      }

      void
      initialize(const ModelState &state, const std::vector<unsigned int> &points) override
      {
        family.initialize(state, points, K, G, material_path, "Viscoelastic");
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

      /// With e^d = e - theta |xi| / 3 and force()'s back extension e^b =
      /// c + beta e^d (c = e^b_N decay + e^d_N (1 - decay - beta), fixed in
      /// the step), W_i = K theta^2 / 2 + alpha / 2 [lambda_inf S + lambda_i
      /// ((1 - beta)^2 S - 2 (1 - beta) sum w c e^d V_j + sum w c^2 V_j)],
      /// S = sum w (e^d)^2 V_j = B - 2 theta A / 3 + theta^2 D / 9 as LPS's:
      /// one pass over the bonds gives both damage states' sums; nothing is
      /// written.
      double
      released_energy(const ModelState &before, const ModelState &now, const std::vector<unsigned int> &points) const override
      {
        const double *m     = now.fields.get(family.weighted_volume).begin();
        const double *alpha = now.fields.get(family.alpha).begin();
        const double *ed_N  = now.fields.bond_old("ves_ed");
        const double *eb_N  = now.fields.bond_old("ves_eb");
        // force()'s integration weights of the step.
        const double dt    = now.dt;
        const double decay = dt > 0 ? std::exp(-dt / tau) : 1.0;
        const double beta  = dt > 0 ? 1 - tau * (1 - decay) / dt : 0.0;
        const double l_inf = 1 - lambda_i;
        // sums: A, B, D as LPS's, C1 = sum w c e, C2 = sum w c |xi|, C3 = sum w c^2.
        return family.released_energy<6>(
          before, now, points,
          [&](const std::size_t b, const double r0, const double e, const double w, double *s) {
            const double c = eb_N[b] * decay + ed_N[b] * (1 - decay) - beta * ed_N[b];
            s[0] += w * r0 * e;
            s[1] += w * e * e;
            s[2] += w * r0 * r0;
            s[3] += w * c * e;
            s[4] += w * c * r0;
            s[5] += w * c * c;
          },
          [&](const unsigned int i, const double *s) {
            const double th = 3 * s[0] / m[i];
            const double S  = s[1] - 2 * th * s[0] / 3 + th * th * s[2] / 9;
            const double Sc = s[3] - th * s[4] / 3; // sum w c e^d V_j
            return 0.5 * K * th * th +
                   0.5 * alpha[i] * (l_inf * S + lambda_i * ((1 - beta) * (1 - beta) * S - 2 * (1 - beta) * Sc + s[5]));
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
        // The instantaneous moduli: the stiffest response, the dashpot's spring unrelaxed.
        return family.stable_time_step(state, points, rho);
      }

      bool
      add_tangent(const ModelState &state, const std::vector<unsigned int> &points, TangentRows &rows) const override
      {
        // e^b_NP1 moves with e^d by beta (the step's integration weight), so the
        // deviatoric half alpha_i (e^d - lambda_i e^b) has the modulus alpha_i
        // (1 - lambda_i beta): LPS's tangent with it (ordinary_state.h).
        const double       *kappa   = state.fields.get(family.kappa).begin();
        const double       *alpha   = state.fields.get(family.alpha).begin();
        const double       *theta   = state.fields.get("ves_dilatation").begin();
        const double       *ed_N    = state.fields.bond_old("ves_ed");
        const double       *eb_N    = state.fields.bond_old("ves_eb");
        const double       *edo_N   = state.fields.bond_old("ves_ed_other");
        const double       *ebo_N   = state.fields.bond_old("ves_eb_other");
        const double        dt      = state.dt;
        const double        decay   = dt > 0 ? std::exp(-dt / tau) : 1.0;
        const double        beta    = dt > 0 ? 1 - tau * (1 - decay) / dt : 0.0;
        const unsigned int  n_local = state.cloud.n_local();
        std::vector<double> deviatoric(n_local);
        for (unsigned int i = 0; i < n_local; ++i)
          deviatoric[i] = alpha[i] * (1 - lambda_i * beta);
        family.add_tangent(state, points, rows, theta, deviatoric.data(), nullptr, nullptr,
                           [&](const unsigned int i, const std::size_t b, const unsigned int j, const double e,
                               const double r0) {
                             const double edi = e - theta[i] * r0 / 3, edj = e - theta[j] * r0 / 3;
                             const double ebi = eb_N[b] * decay + ed_N[b] * (1 - decay) + beta * (edi - ed_N[b]);
                             const double ebj = ebo_N[b] * decay + edo_N[b] * (1 - decay) + beta * (edj - edo_N[b]);
                             return OrdinaryState::bond_weight(state, b) *
                                    (r0 * (kappa[i] * theta[i] + kappa[j] * theta[j]) + alpha[i] * (edi - lambda_i * ebi) +
                                     alpha[j] * (edj - lambda_i * ebj));
                           });
        return true;
      }

    private:
      /// (1/tau) int v^2 dt over a step of e^d linear in time, with the
      /// exact e^b (the header's formula): the weights of v_N^2, v_N Delta
      /// and Delta^2, fixed in the step. dt = 0: all 0.
      struct DissipationWeights
      {
        DissipationWeights(const double dt, const double tau)
        {
          if (!(dt > 0))
            return;
          const double a = dt / tau; // may be inf for tau far below dt: the limits hold
          const double one_minus_decay = -std::expm1(-a);
          c_nn = -0.5 * std::expm1(-2 * a);
          c_nd = one_minus_decay * one_minus_decay / a;
          // g(a)/a^2, written to give 0 at a = inf. The closed form cancels
          // for small a (relative error eps/a^2): below a = 3e-3 its series
          // (truncated at a relative a^4 / 10); either way about 1e-10.
          c_dd = a < 3e-3 ? a * (1.0 / 3 - a * (0.25 - a * (7.0 / 60 - a / 24))) :
                            (1 - (2 * one_minus_decay - c_nn) / a) / a;
        }
        double
        integral(const double v_N, const double delta) const
        {
          return c_nn * v_N * v_N + c_nd * v_N * delta + c_dd * delta * delta;
        }
        double c_nn = 0, c_nd = 0, c_dd = 0;
      };

      double              rho = 0, K = 0, G = 0, tau = 1, lambda_i = 0.5, alpha_T = 0;
      std::string         material_path;

      /// The dilatation; with @p breaking, first the fused critical stretch.
      template <bool weighted, bool periodic, bool damaged, bool thermal, bool breaking>
      void
      stage(const ModelState &state, const std::vector<unsigned int> &points) const
      {
        std::size_t         newly_broken = 0;
        const double       *V        = state.cloud.volume.data();
        const std::size_t  *offsets  = state.bonds.offsets.data();
        const unsigned int *neighbor = state.bonds.neighbor.data();
        const double       *m        = state.fields.get(family.weighted_volume).begin();
        double             *theta    = state.fields.get("ves_dilatation").begin();
        for (const unsigned int i : points)
          {
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
            theta[i] = m[i] > 0 ? 3 * sum / m[i] : 0.0;
          }
        if constexpr (breaking)
          state.breaking->newly_broken += newly_broken;
      }

      template <bool weighted, bool periodic, bool damaged, bool thermal, bool energy, bool bond_work>
      void
      force(const ModelState &state, const std::vector<unsigned int> &points) const
      {
        const auto work_update = bond_work ? OrdinaryState::WorkUpdate(state, family) : OrdinaryState::WorkUpdate();
        const double       *V        = state.cloud.volume.data();
        const std::size_t  *offsets  = state.bonds.offsets.data();
        const unsigned int *neighbor = state.bonds.neighbor.data();
        const double       *kappa    = state.fields.get(family.kappa).begin();
        const double       *alpha    = state.fields.get(family.alpha).begin();
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
        const DissipationWeights weights(dt, tau);
        for (const unsigned int i : points)
          {
            const BondOrigin origin(state.cloud.X.data(), state.u, i);
            const double     ti = theta[i], ki = kappa[i] * ti, ai = alpha[i];
            double           fx = 0, fy = 0, fz = 0, Wd = 0, dissipated = 0;
            for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
              {
                const unsigned int j = neighbor[b];
                double             y[3], r0, r, e;
                OrdinaryState::bond<periodic, thermal>(state, origin, i, j, y, r0, r, e);
                const double edi = e - ti * r0 / 3;
                const double edj = e - theta[j] * r0 / 3;
                const double ebi = eb_N[b] * decay + ed_N[b] * (1 - decay) + beta * (edi - ed_N[b]);
                const double ebj = ebo_N[b] * decay + edo_N[b] * (1 - decay) + beta * (edj - edo_N[b]);
                ed_NP1[b]        = edi;
                eb_NP1[b]        = ebi;
                edo_NP1[b]       = edj;
                ebo_NP1[b]       = ebj;
                const double w   = OrdinaryState::weight<weighted, damaged>(state, b);
                const double t   = w * (r0 * (ki + kappa[j] * theta[j]) + ai * (edi - lambda_i * ebi) +
                                      alpha[j] * (edj - lambda_i * ebj));
                // t again, with the two ends' terms added alike on both owners.
                if constexpr (bond_work)
                  work_update.add(b,
                                  w * (r0 * OrdinaryState::symmetric_sum(ki, kappa[j] * theta[j]) +
                                       OrdinaryState::symmetric_sum(ai * (edi - lambda_i * ebi),
                                                                    alpha[j] * (edj - lambda_i * ebj))),
                                  e);
                const double k   = t * V[j] / r;
                fx += k * y[0];
                fy += k * y[1];
                fz += k * y[2];
                const double v_N = ed_N[b] - eb_N[b], v = edi - ebi;
                dissipated += w * weights.integral(v_N, edi - ed_N[b]) * V[j];
                if (energy)
                  Wd += w * (l_inf * edi * edi + lambda_i * v * v) * V[j];
              }
            f[3 * i] += fx;
            f[3 * i + 1] += fy;
            f[3 * i + 2] += fz;
            Dv[i] = D_N[i] + ai * lambda_i * dissipated;
            if (energy)
              state.energy[i] += 0.5 * K * ti * ti + 0.5 * ai * Wd;
          }
      }
    };
  } // namespace

  PERIDEAL_REGISTER(Material, Viscoelastic, "Viscoelastic",
                    "Mitchell's ordinary state-based viscoelastic solid: LPS (omega = 1) with an elastic "
                    "dilatation and a standard-linear-solid deviatoric part (Peridigm's 'Viscoelastic'). "
                    "Keys: Density, two of Bulk modulus, Shear modulus, Young's modulus, Poisson's ratio (the "
                    "instantaneous ones), Relaxation time, Viscous fraction, Thermal expansion coefficient.")
} // namespace perideal
