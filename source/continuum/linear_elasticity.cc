#include <perideal/base/format.h>
#include <perideal/continuum/linear_elasticity.h>
#include <perideal/material/material.h>

#include <deal.II/fe/fe_values_extractors.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <algorithm>
#include <cmath>

namespace perideal
{
  using namespace dealii;

  LinearElasticity::LinearElasticity(const double K, const double G, const double rho)
    : K(K)
    , G(G)
    , rho(rho)
    , lambda(K - 2 * G / 3)
    , mu(G)
  {
    AssertThrow(K > 0 && G > 0 && rho > 0,
                ExcMessage("linear elasticity needs a positive bulk modulus, shear modulus and density"));
  }

  void
  LinearElasticity::initialize(const Material &material)
  {
    *this = LinearElasticity(material.bulk_modulus(), material.shear_modulus(), material.density());
  }

  std::string
  LinearElasticity::describe() const
  {
    return "E " + sci(young_modulus()) + ", nu " + sci(poisson_ratio(), 4);
  }

  void
  LinearElasticity::cell_matrix(const FEValues<dim> &fe_values, FullMatrix<double> &matrix) const
  {
    const FEValuesExtractors::Vector u(0);
    const unsigned int               n = fe_values.dofs_per_cell;
    matrix.reinit(n, n);
    std::vector<SymmetricTensor<2, dim>> eps(n);
    std::vector<double>                  div(n);
    for (const unsigned int q : fe_values.quadrature_point_indices())
      {
        for (unsigned int i = 0; i < n; ++i)
          {
            eps[i] = fe_values[u].symmetric_gradient(i, q);
            div[i] = trace(eps[i]);
          }
        const double JxW = fe_values.JxW(q);
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = i; j < n; ++j)
            matrix(i, j) += (lambda * div[i] * div[j] + 2 * mu * (eps[i] * eps[j])) * JxW;
      }
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < i; ++j)
        matrix(i, j) = matrix(j, i);
  }

  void
  LinearElasticity::cell_lumped_mass(const FEValues<dim> &fe_values, Vector<double> &mass) const
  {
    // Row sum of rho int phi_i . phi_j: the components do not mix, and the
    // scalar shape functions sum to one, so the row sum is rho int N_i.
    const unsigned int n = fe_values.dofs_per_cell;
    mass.reinit(n);
    const auto &fe = fe_values.get_fe();
    for (const unsigned int q : fe_values.quadrature_point_indices())
      for (unsigned int i = 0; i < n; ++i)
        mass(i) += rho * fe_values.shape_value_component(i, q, fe.system_to_component_index(i).first) *
                   fe_values.JxW(q);
  }

  namespace
  {
    // int phi_i . v over the quadrature of @p fe_values (cell or face).
    template <class FEValuesType>
    void
    constant_load(const FEValuesType &fe_values, const Tensor<1, dim> &v, Vector<double> &load)
    {
      const unsigned int n  = fe_values.dofs_per_cell;
      const auto        &fe = fe_values.get_fe();
      load.reinit(n);
      for (const unsigned int q : fe_values.quadrature_point_indices())
        for (unsigned int i = 0; i < n; ++i)
          {
            const unsigned int c = fe.system_to_component_index(i).first;
            load(i) += v[c] * fe_values.shape_value_component(i, q, c) * fe_values.JxW(q);
          }
    }
  } // namespace

  void
  LinearElasticity::cell_body_force(const FEValues<dim> &fe_values, const Tensor<1, dim> &b, Vector<double> &load)
  {
    constant_load(fe_values, b, load);
  }

  void
  LinearElasticity::face_traction(const FEFaceValues<dim> &fe_face_values, const Tensor<1, dim> &t, Vector<double> &load)
  {
    constant_load(fe_face_values, t, load);
  }

  double
  LinearElasticity::stable_time_step(const FullMatrix<double> &cell_matrix, const Vector<double> &cell_mass)
  {
    // M^-1/2 K M^-1/2 is symmetric with the eigenvalues of M^-1 K.
    const unsigned int     n = cell_mass.size();
    LAPACKFullMatrix<double> A(n, n);
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        A(i, j) = cell_matrix(i, j) / std::sqrt(cell_mass(i) * cell_mass(j));
    const double scale = A.frobenius_norm();
    Vector<double>     eigenvalues;
    FullMatrix<double> eigenvectors;
    A.compute_eigenvalues_symmetric(-scale, 2 * scale, 0, eigenvalues, eigenvectors);
    double largest = 0;
    for (const double l : eigenvalues)
      largest = std::max(largest, l);
    return largest > 0 ? 2 / std::sqrt(largest) : std::numeric_limits<double>::max();
  }
  PERIDEAL_REGISTER(ContinuumModel, LinearElasticity, "Linear elasticity",
                    "FE_Q(FE degree) linear elasticity with the material's bulk modulus, shear modulus and "
                    "density.")
} // namespace perideal
