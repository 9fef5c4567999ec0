// Elastic correspondence material (state based, non-ordinary; Peridigm's
// "Elastic Correspondence"): a classical elastic stress law through the
// nonlocal deformation gradient F of include/perideal/material/correspondence.h
// (shape tensor, force state, stabilization, damage, stable time step there).
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

#include <perideal/material/correspondence.h>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class ElasticCorrespondence : public CorrespondenceMaterial
    {
    public:
      ElasticCorrespondence()
        : CorrespondenceMaterial("Elastic correspondence")
      {}

      static void
      declare_parameters(ParameterHandler &prm)
      {
        declare_kinematics_parameters(prm);
        prm.declare_entry("Strain measure", "Green-Lagrange", Patterns::Selection("Green-Lagrange|Small strain"),
                          "Green-Lagrange: St. Venant-Kirchhoff, S = lambda tr(E) I + 2 G E, E = (F^T F - I)/2, "
                          "P = F S. Small strain: corotational Hooke, F = R U, eps = U - I, sigma = R (lambda "
                          "tr(eps) I + 2 G eps) R^T, P = J sigma F^-T. Both give zero stress under any rigid "
                          "rotation.");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path_) override
      {
        parse_kinematics_parameters(prm, path_);
        small_strain = prm.get("Strain measure") == "Small strain";
      }

      void
      compute_stage(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        compute_deformation(
          state,
          points,
          [&](unsigned int, const double *F, const double theta, double *P, double *sigma, double &W) {
            stress(F, theta, P, sigma, W);
          },
          [](unsigned int) {});
      }

    private:
      bool small_strain = false;

      /// First Piola-Kirchhoff P, Cauchy stress and energy density W of F
      /// (row-major), with the thermal stretch theta = 1 + alpha dT.
      void
      stress(const double *F, const double theta, double *P, double *sigma, double &W) const
      {
        using namespace correspondence;
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
            double R[9], U[9], Uinv[9], eps[9], EE = 0;
            polar_decomposition(Fe, R, U, Uinv);
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
    };
  } // namespace

  PERIDEAL_REGISTER(Material, ElasticCorrespondence, "Elastic correspondence",
                    "Non-ordinary state-based correspondence model: a nonlocal deformation gradient F = "
                    "(sum w Y (x) xi V) K^-1 and an elastic stress law (St. Venant-Kirchhoff or corotational "
                    "small strain), with hourglass or Silling (2017) stabilization of its zero-energy modes. "
                    "Keys: Density, two of Bulk modulus, Shear modulus, Young's modulus, Poisson's ratio, "
                    "Strain measure, Stabilization, Hourglass coefficient, Silling coefficient, Thermal "
                    "expansion coefficient.")
} // namespace perideal
