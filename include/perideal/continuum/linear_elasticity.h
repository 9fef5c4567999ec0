#pragma once
// Linear elasticity on FE_Q(p)^dim cells: the continuum model of the blocks
// that do not break (doc/coupling.md). Per cell: the stiffness matrix
//   K_ij = int lambda div(phi_i) div(phi_j) + 2 mu eps(phi_i) : eps(phi_j),
// the row-sum lumped mass, and the load of a body force or a face traction.
// The stable explicit step of the assembled, lumped system follows from the
// element eigenvalue bound: omega_max^2 <= max_e lambda_max(M_e^-1 K_e)
// (the largest frequency of the assembly is at most the largest of its
// elements), dt <= 2 / omega_max.
// K, G and rho are those of the PD material of the same name, so that a block
// can switch between PD and FE without changing the material. Registered as
// the ContinuumModel "Linear elasticity".

#include <perideal/continuum/continuum_model.h>

#include <deal.II/base/tensor.h>

namespace perideal
{
  class LinearElasticity : public ContinuumModel
  {
  public:
    /// Constants from initialize().
    LinearElasticity() = default;
    /// Bulk modulus K, shear modulus G, density rho; all must be positive.
    LinearElasticity(const double K, const double G, const double rho);

    /// K, G and rho of @p material.
    void
    initialize(const Material &material) override;

    /// The cell stiffness matrix. @p fe_values is reinit'ed on the cell with
    /// update_gradients and update_JxW_values, its element an FESystem of
    /// dim scalar components.
    void
    cell_matrix(const dealii::FEValues<dim> &fe_values, dealii::FullMatrix<double> &matrix) const override;

    /// The cell's row sums of the consistent mass matrix, rho int phi_i (the
    /// lumped mass; positive for Lagrange Q1 and Q2). Needs update_values.
    void
    cell_lumped_mass(const dealii::FEValues<dim> &fe_values, dealii::Vector<double> &mass) const override;

    double
    density() const override
    {
      return rho;
    }

    std::vector<double>
    constants() const override
    {
      return {K, G, rho};
    }

    /// "E ..., nu ...".
    std::string
    describe() const override;

    /// int phi_i . b over the cell for a constant body force density @p b
    /// (force per volume). Needs update_values.
    static void
    cell_body_force(const dealii::FEValues<dim> &fe_values,
                    const dealii::Tensor<1, dim> &b,
                    dealii::Vector<double>      &load);

    /// int phi_i . t over a face for a constant traction @p t (force per
    /// area). Needs update_values and update_JxW_values.
    static void
    face_traction(const dealii::FEFaceValues<dim> &fe_face_values,
                  const dealii::Tensor<1, dim>   &t,
                  dealii::Vector<double>        &load);

    /// The stable step of an explicit central-difference (velocity-Verlet)
    /// step for one element: 2 / sqrt(lambda_max(M^-1 K)) of its stiffness
    /// matrix and lumped mass (LAPACK, symmetric). The minimum over the
    /// elements bounds the step of the assembled lumped system from below.
    static double
    stable_time_step(const dealii::FullMatrix<double> &cell_matrix, const dealii::Vector<double> &cell_mass);

    double
    young_modulus() const
    {
      return 9 * K * G / (3 * K + G);
    }
    double
    poisson_ratio() const
    {
      return (3 * K - 2 * G) / (2 * (3 * K + G));
    }
    double
    p_wave_speed() const
    {
      return std::sqrt((K + 4 * G / 3) / rho);
    }

    double K = 0, G = 0, rho = 0;
    double lambda = 0, mu = 0;
  };
} // namespace perideal
