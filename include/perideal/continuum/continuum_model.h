#pragma once
// The constitutive model of a continuum (FE) block: its cell matrices, from
// the constants of the block's material. A plugin registered with
// PERIDEAL_REGISTER(ContinuumModel, Class, "Name", "doc"); today's only one
// is Linear elasticity (linear_elasticity.cc), which every continuum block
// takes (no key chooses the model yet: simulation/deck.cc).

#include <perideal/base/input.h>
#include <perideal/base/registry.h>

#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <string>
#include <vector>

namespace perideal
{
  class Material;

  class ContinuumModel
  {
  public:
    /// A continuum model has no keys of its own: it takes its material's.
    static void
    declare_parameters(ParameterHandler &)
    {}

    virtual ~ContinuumModel() = default;

    /// Takes the constants of the block's @p material (the PD material of
    /// the same name, so that a block can switch between PD and FE without
    /// changing the material); throws if they do not fit the model.
    virtual void
    initialize(const Material &material) = 0;

    /// The cell stiffness matrix. @p fe_values is reinit'ed on the cell with
    /// update_values, update_gradients and update_JxW_values, its element an
    /// FESystem of dim scalar components.
    virtual void
    cell_matrix(const dealii::FEValues<dim> &fe_values, dealii::FullMatrix<double> &matrix) const = 0;

    /// The cell's lumped mass per DoF (positive).
    virtual void
    cell_lumped_mass(const dealii::FEValues<dim> &fe_values, dealii::Vector<double> &mass) const = 0;

    /// Mass density (the lumped volume of a node is its mass over it).
    virtual double
    density() const = 0;

    /// The constants on which the cell matrices depend besides the cell:
    /// cells alike with equal constants share their stable step.
    virtual std::vector<double>
    constants() const = 0;

    /// The constants for the set-up report, e.g. "E 2e+11, nu 0.3".
    virtual std::string
    describe() const = 0;
  };
} // namespace perideal
