// The numbering of the mechanical DoFs, points' and FE's (state.h).

#include <perideal/continuum/continuum_field.h>
#include <perideal/discretization/discretization.h>
#include <perideal/model/state.h>
#include <perideal/output/checkpoint.h>

#include <deal.II/base/mpi.h>

namespace perideal
{
  using namespace dealii;

  void
  MechanicalState::number_dofs(const Discretization &discretization_, ContinuumField *continuum_)
  {
    static const std::vector<unsigned int> no_dofs;
    discretization  = &discretization_;
    continuum       = continuum_;
    const auto &cloud = discretization->cloud;
    n_point_entries = dim * cloud.n_owned();
    point_measure   = cloud.volume.data();
    point_inverse_density.resize(cloud.n_owned());
    for (unsigned int i = 0; i < cloud.n_owned(); ++i)
      point_inverse_density[i] = mass_density[i] > 0 ? 1 / mass_density[i] : 0.0; // virtual points: no mass
    fe_free = continuum ? &continuum->free : &no_dofs;
    n_fe    = continuum ? continuum->U.locally_owned_size() : 0;
    if (continuum)
      {
        U = continuum->U.begin();
        V = continuum->V.begin();
        F = continuum->F.begin();
        M = continuum->mass.begin();
        fe_inverse_mass.assign(n_fe, 0.0);
        fe_moves.assign(n_fe, 0);
        for (const unsigned int l : *fe_free)
          {
            fe_inverse_mass[l] = 1 / M[l];
            fe_moves[l]        = 1;
          }
        node_of.assign(n_fe, numbers::invalid_unsigned_int);
        for (unsigned int k = 0; k < continuum->nodes.size(); ++k)
          node_of[continuum->nodes[k].local] = k;
        hanging = Utilities::MPI::sum(continuum->hanging.n_constraints(), continuum->U.get_mpi_communicator()) > 0;
      }
  }

  double &
  MechanicalState::u(const unsigned int k)
  {
    return is_fe(k) ? U[fe_local(k)] : displacement.local_element(k);
  }

  double
  MechanicalState::u(const unsigned int k) const
  {
    return is_fe(k) ? U[fe_local(k)] : displacement.local_element(k);
  }

  double &
  MechanicalState::v(const unsigned int k)
  {
    return is_fe(k) ? V[fe_local(k)] : velocity.local_element(k);
  }

  double
  MechanicalState::v(const unsigned int k) const
  {
    return is_fe(k) ? V[fe_local(k)] : velocity.local_element(k);
  }

  double
  MechanicalState::f(const unsigned int k) const
  {
    return is_fe(k) ? F[fe_local(k)] : force.local_element(k);
  }

  double
  MechanicalState::measure(const unsigned int k) const
  {
    return is_fe(k) ? 1.0 : point_measure[point(k)];
  }

  double
  MechanicalState::density(const unsigned int k) const
  {
    return is_fe(k) ? M[fe_local(k)] : mass_density[point(k)];
  }

  bool
  MechanicalState::is_virtual(const unsigned int k) const
  {
    return !is_fe(k) && discretization->is_virtual(point(k));
  }

  Point<dim>
  MechanicalState::position(const unsigned int k) const
  {
    return is_fe(k) ? continuum->nodes[node_of[fe_local(k)]].x : discretization->cloud.position(point(k));
  }

  unsigned int
  MechanicalState::component(const unsigned int k) const
  {
    return is_fe(k) ? continuum->nodes[node_of[fe_local(k)]].component : k % dim;
  }

  std::uint64_t
  MechanicalState::hash(const unsigned int k) const
  {
    return is_fe(k) ? 0 : discretization->cloud.hash(point(k));
  }

  void
  MechanicalState::distribute_displacement()
  {
    if (hanging)
      continuum->hanging.distribute(continuum->U);
  }

  void
  MechanicalState::distribute_velocity()
  {
    if (hanging)
      continuum->hanging.distribute(continuum->V);
  }

  void
  MechanicalState::save(CheckpointWriter &out) const
  {
    out.section("mechanical state");
    out.put(size());
    for (unsigned int k = 0; k < size(); ++k)
      out.put(u(k));
    for (unsigned int k = 0; k < size(); ++k)
      out.put(v(k));
    for (unsigned int k = 0; k < size(); ++k)
      out.put(f(k));
    out.put(acceleration);
  }

  void
  MechanicalState::load(CheckpointReader &in)
  {
    in.section("mechanical state");
    const unsigned int n = in.get<unsigned int>();
    in.expect(n == size(), "the body has " + std::to_string(size()) + " degrees of freedom on this rank, " +
                             std::to_string(n) + " in the checkpoint");
    for (unsigned int k = 0; k < n; ++k)
      in.get(u(k));
    for (unsigned int k = 0; k < n; ++k)
      in.get(v(k));
    for (unsigned int k = 0; k < n; ++k)
      in.get(is_fe(k) ? continuum->F.local_element(fe_local(k)) : force.local_element(k));
    in.get(acceleration);
  }

  void
  RunRecord::save(CheckpointWriter &out) const
  {
    out.section("run record");
    for (const double x : {dt, dt_stable, external_work, initial_energy, last_strain_energy, last_kinetic_energy,
                           dissipated_energy, material_dissipation, last_contact_energy, contact_dissipation,
                           shortest_dt, last_newton.residual, smallest_step_fraction, conversion_energy,
                           converted_cells, conversion_seconds})
      out.put(x);
    for (const unsigned int n : {shortened_steps, last_newton.newton_iterations, last_newton.linear_iterations,
                                 last_damage_solves, step_cuts, conversions})
      out.put(n);
    out.put(warnings);
  }

  void
  RunRecord::load(CheckpointReader &in)
  {
    in.section("run record");
    for (double *x : {&dt, &dt_stable, &external_work, &initial_energy, &last_strain_energy, &last_kinetic_energy,
                      &dissipated_energy, &material_dissipation, &last_contact_energy, &contact_dissipation,
                      &shortest_dt, &last_newton.residual, &smallest_step_fraction, &conversion_energy,
                      &converted_cells, &conversion_seconds})
      in.get(*x);
    for (unsigned int *n : {&shortened_steps, &last_newton.newton_iterations, &last_newton.linear_iterations,
                            &last_damage_solves, &step_cuts, &conversions})
      in.get(*n);
    in.get(warnings);
  }

  void
  MechanicalState::set_velocity_zero()
  {
    velocity = 0;
    if (continuum)
      continuum->V = 0;
  }
} // namespace perideal
