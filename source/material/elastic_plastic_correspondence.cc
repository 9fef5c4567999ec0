// Elastic plastic correspondence material (state based, non-ordinary;
// Peridigm's "Elastic Plastic Correspondence" and "Elastic Plastic Hardening
// Correspondence"): J2 plasticity with linear isotropic hardening, hypoelastic
// in the unrotated frame, through the nonlocal deformation gradient F of
// include/perideal/material/correspondence.h (shape tensor, force state,
// stabilization, damage, stable time step there).
// Kinematics of the law: the elastic part F_e = F / theta (theta = 1 + alpha
// dT) = R U by the polar decomposition, taken anew at every evaluation (R is
// not integrated over the steps, so it cannot drift).
// Unrotated rate of deformation (Flanagan & Taylor 1987, as Peridigm's
// correspondence plasticity): with D = sym(dF/dt F^-1), d = R^T D R =
// sym(dU/dt U^-1), since R^T dR/dt is skew. Over the step N -> NP1, by the
// midpoint rule,
//   De = sym((U_NP1 - U_N) U_mid^-1),  U_mid = (U_N + U_NP1) / 2.
// It depends on U only: a rotation of any size superposed on the step
// (F_NP1 = Q F) leaves everything in the unrotated frame unchanged, and a
// rigid motion (U = I) has no strain and no stress. On a path of fixed
// principal axes it sums to the logarithmic strain (to third order in each
// increment). The law is rate independent: it needs no dt, only the stretch
// U_N of the last accepted state (history); at the initial evaluation of an
// undeformed body U = U_N = I and there is no increment.
// Stress: an unrotated stress S^ updated by backward Euler and radial return
// (Simo & Hughes, box 3.1), with lambda = K - 2G/3 and Y_N = Y0 + H eps_p,N:
//   S_tr = S^_N + lambda tr(De) I + 2 G De,  s_tr = dev S_tr,
//   q_tr = sqrt(3/2 s_tr:s_tr);  if q_tr > Y_N:
//   a = (q_tr - Y_N) / (3G + H),  s = s_tr (Y_N + H a) / q_tr,  eps_p += a,
// else s = s_tr, a = 0; S^_NP1 = s + tr(S_tr)/3 I. Which stress S^ is, the
// key 'Yield stress measure' says:
// - Kirchhoff (the default): S^ = tau^, the unrotated Kirchhoff stress (J
//   times the unrotated Cauchy stress). The work per unit reference volume
//   is the integral of tau:D dt, so with the stored energy density
//   W = tau^:C^-1:tau^ / 2 = p^2 / (2K) + s:s / (4G)   (p = tr(tau^)/3)
//   and the dissipation D_NP1 = D_N + (Y_N + H a / 2) a, work = W + D holds
//   to the error of the time integration. The Cauchy von Mises stress at
//   yield is Y / J.
//     P = R tau^ U^-1 / theta (= tau F^-T),  sigma = R tau^ R^T / det F.
// - Cauchy (Peridigm's): S^ = sigma^, the unrotated Cauchy stress, so the
//   Cauchy von Mises stress at yield is Y. With J = det F,
//     P = J R sigma^ U^-1 / theta,  sigma = R sigma^ R^T,
//     W = J (p^2 / (2K) + s:s / (4G)),  D_NP1 = D_N + J (Y_N + H a / 2) a;
//   work = W + D then holds to O(tr(De) W) per step besides (the Cauchy
//   rate is not the one whose work is tau:D).
// W is not a potential of the force (the stress depends on the path).
// History per point: S^ (6), U - I (6), the equivalent plastic strain
// eps_p (output "Equivalent plastic strain", the field of Elastic plastic),
// and D (a dissipation field: the globals' material_dissipation and the
// energy balance include it). A point whose damaged family no longer spans
// space carries no stress and keeps its history.
// Tangent: none analytic; the implicit solvers use finite differences.

#include <perideal/material/correspondence.h>

#include <cmath>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class ElasticPlasticCorrespondence : public CorrespondenceMaterial
    {
    public:
      ElasticPlasticCorrespondence()
        : CorrespondenceMaterial("Elastic plastic correspondence")
      {}

      static void
      declare_parameters(ParameterHandler &prm)
      {
        declare_kinematics_parameters(prm);
        prm.declare_entry("Yield stress", "0", Patterns::Double(),
                          "Initial von Mises yield stress Y0 > 0 (Peridigm's 'Yield Stress').");
        prm.declare_entry("Hardening modulus", "0", Patterns::Double(),
                          "Linear isotropic hardening H >= 0: Y = Y0 + H eps_p, eps_p the equivalent plastic "
                          "strain (uniaxial stress: tangent modulus E H / (E + H)); 0: perfectly plastic.");
        prm.declare_entry("Yield stress measure", "Kirchhoff", Patterns::Selection("Kirchhoff|Cauchy"),
                          "The stress whose von Mises value yields at Y: Kirchhoff (J times Cauchy; the stored "
                          "and dissipated energies add up to the work exactly; the Cauchy von Mises stress at "
                          "yield is Y / J) or Cauchy (Peridigm's: the Cauchy von Mises stress at yield is Y). "
                          "The two differ by the volume ratio J = det F (doc/models.md).");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path_) override
      {
        parse_kinematics_parameters(prm, path_);
        Y0 = prm.get_double("Yield stress");
        H  = prm.get_double("Hardening modulus");
        cauchy_yield = prm.get("Yield stress measure") == "Cauchy";
        require_positive(Y0, path + "/Yield stress");
        AssertThrow(H >= 0 && std::isfinite(H),
                    ExcMessage(path + "/Hardening modulus must be >= 0 (0: perfectly plastic), got " +
                               prm.get("Hardening modulus")));
      }

      std::vector<PointField>
      point_fields() const override
      {
        std::vector<PointField> f = CorrespondenceMaterial::point_fields();
        f.push_back({"epc_stress", FieldUse::history, 6});  // S^: tau^ or sigma^ (see the top)
        f.push_back({"epc_stretch", FieldUse::history, 6}); // U - I
        // The fields of Elastic plastic: one output variable for both models.
        f.push_back({"eps_plastic_strain", FieldUse::history, 1, "Equivalent plastic strain"});
        f.push_back({"eps_dissipation", FieldUse::history, 1, "Plastic dissipation density", true});
        return f;
      }

      void
      compute_stage(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        const double *tau_N = state.fields.old("epc_stress").begin();
        const double *U_N   = state.fields.old("epc_stretch").begin();
        const double *ep_N  = state.fields.old("eps_plastic_strain").begin();
        const double *D_N   = state.fields.old("eps_dissipation").begin();
        double       *tau   = state.fields.get("epc_stress").begin();
        double       *U     = state.fields.get("epc_stretch").begin();
        double       *ep    = state.fields.get("eps_plastic_strain").begin();
        double       *D     = state.fields.get("eps_dissipation").begin();
        compute_deformation(
          state,
          points,
          [&](const unsigned int i, const double *F, const double theta, double *P, double *sigma, double &W) {
            ep[i] = ep_N[i];
            D[i]  = D_N[i];
            W     = stress(F, theta, tau_N + 6 * i, U_N + 6 * i, tau + 6 * i, U + 6 * i, ep[i], D[i], P, sigma);
          },
          [&](const unsigned int i) {
            for (unsigned int k = 0; k < 6; ++k)
              tau[6 * i + k] = tau_N[6 * i + k], U[6 * i + k] = U_N[6 * i + k];
            ep[i] = ep_N[i];
            D[i]  = D_N[i];
          });
      }

    private:
      double Y0 = 0, H = 0;
      bool   cauchy_yield = false; // Yield stress measure: S^ is sigma^ (true) or tau^

      /// Symmetric 6-vector (xx yy zz xy yz xz) <-> row-major 3x3.
      static void
      full(const double *s, double *A)
      {
        A[0] = s[0], A[4] = s[1], A[8] = s[2];
        A[1] = A[3] = s[3], A[5] = A[7] = s[4], A[2] = A[6] = s[5];
      }

      /// The step N -> NP1 of one point (see the top): from F, the thermal
      /// stretch theta and the history at N (tau^_N, U_N - I), the history at
      /// NP1 (tau^, U - I; eps_p and D updated in place), P and the Cauchy
      /// stress; returns the stored energy density W.
      double
      stress(const double *F,
             const double  theta,
             const double *tau_N,
             const double *stretch_N,
             double       *tau,
             double       *stretch,
             double       &ep,
             double       &D,
             double       *P,
             double       *sigma) const
      {
        using namespace correspondence;
        double Fe[9], R[9], Un[9], Uinv[9];
        for (unsigned int k = 0; k < 9; ++k)
          Fe[k] = F[k] / theta;
        polar_decomposition(Fe, R, Un, Uinv);

        // De = sym(dU U_mid^-1), dU from U - I (no cancellation against I).
        double dU[9], Umid[9], Uold[9];
        full(stretch_N, Uold);
        for (unsigned int k = 0; k < 9; ++k)
          {
            const double I = k % 4 == 0 ? 1.0 : 0.0;
            dU[k]          = (Un[k] - I) - Uold[k];
            Umid[k]        = I + 0.5 * (Uold[k] + (Un[k] - I));
          }
        const double adj[9] = {Umid[4] * Umid[8] - Umid[5] * Umid[7], Umid[2] * Umid[7] - Umid[1] * Umid[8],
                               Umid[1] * Umid[5] - Umid[2] * Umid[4], Umid[5] * Umid[6] - Umid[3] * Umid[8],
                               Umid[0] * Umid[8] - Umid[2] * Umid[6], Umid[2] * Umid[3] - Umid[0] * Umid[5],
                               Umid[3] * Umid[7] - Umid[4] * Umid[6], Umid[1] * Umid[6] - Umid[0] * Umid[7],
                               Umid[0] * Umid[4] - Umid[1] * Umid[3]};
        const double det    = Umid[0] * adj[0] + Umid[1] * adj[3] + Umid[2] * adj[6];
        double       L[9];
        multiply(dU, adj, L); // dU adj(U_mid) = det(U_mid) dU U_mid^-1
        const double s = 1 / det;
        const double De[6] = {L[0] * s, L[4] * s, L[8] * s, 0.5 * (L[1] + L[3]) * s, 0.5 * (L[5] + L[7]) * s,
                              0.5 * (L[2] + L[6]) * s};
        for (unsigned int k = 0; k < 6; ++k)
          stretch[k] = k < 3 ? Un[4 * k] - 1 : Un[k == 3 ? 1 : k == 4 ? 5 : 2];

        // Elastic trial and radial return on S^ (tau^ or sigma^).
        const double lambda = K - 2 * G / 3, trace = De[0] + De[1] + De[2];
        double       t[6];
        for (unsigned int k = 0; k < 6; ++k)
          t[k] = tau_N[k] + 2 * G * De[k] + (k < 3 ? lambda * trace : 0.0);
        const double p = (t[0] + t[1] + t[2]) / 3;
        double       dev[6];
        for (unsigned int k = 0; k < 6; ++k)
          dev[k] = t[k] - (k < 3 ? p : 0.0);
        const double ss   = dev[0] * dev[0] + dev[1] * dev[1] + dev[2] * dev[2] +
                          2 * (dev[3] * dev[3] + dev[4] * dev[4] + dev[5] * dev[5]);
        const double q_tr = std::sqrt(1.5 * ss), Y_N = Y0 + H * ep;
        // Energies per unit reference volume: J times those of a Cauchy S^.
        const double J = determinant(F), per_reference = cauchy_yield ? J : 1.0;
        double       scale = 1;
        if (q_tr > Y_N)
          {
            const double a = (q_tr - Y_N) / (3 * G + H);
            scale          = (Y_N + H * a) / q_tr;
            D += per_reference * (Y_N + 0.5 * H * a) * a;
            ep += a;
          }
        for (unsigned int k = 0; k < 6; ++k)
          tau[k] = scale * dev[k] + (k < 3 ? p : 0.0);

        // With tau^ = per_reference S^: P = R tau^ U^-1 / theta, sigma = R tau^ R^T / det F.
        double T[9], RT[9], TUinv[9];
        full(tau, T);
        multiply(R, T, RT);
        multiply(RT, Uinv, TUinv);
        for (unsigned int k = 0; k < 9; ++k)
          P[k] = per_reference * TUinv[k] / theta;
        for (unsigned int a = 0; a < 3; ++a)
          for (unsigned int b = 0; b < 3; ++b)
            sigma[3 * a + b] =
              (RT[3 * a] * R[3 * b] + RT[3 * a + 1] * R[3 * b + 1] + RT[3 * a + 2] * R[3 * b + 2]) * per_reference / J;
        return per_reference * (p * p / (2 * K) + scale * scale * ss / (4 * G));
      }
    };
  } // namespace

  PERIDEAL_REGISTER(Material, ElasticPlasticCorrespondence, "Elastic plastic correspondence",
                    "Non-ordinary state-based correspondence model with J2 plasticity: the nonlocal "
                    "deformation gradient of Elastic correspondence, a hypoelastic stress in the unrotated "
                    "frame (polar decomposition, Flanagan-Taylor rate), von Mises yield with linear "
                    "isotropic hardening by radial return (Peridigm's 'Elastic Plastic Correspondence' and "
                    "'Elastic Plastic Hardening Correspondence'). Keys: Density, any two of Bulk modulus, "
                    "Shear modulus, Young's modulus, Poisson's ratio, Yield stress, Hardening modulus, "
                    "Yield stress measure, "
                    "Stabilization, Hourglass coefficient, Silling coefficient, Thermal expansion coefficient.")
} // namespace perideal
