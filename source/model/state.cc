// The numbering of the mechanical DoFs, points' and FE's (state.h).

#include <perideal/continuum/continuum_field.h>
#include <perideal/discretization/discretization.h>
#include <perideal/model/state.h>

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
  MechanicalState::set_velocity_zero()
  {
    velocity = 0;
    if (continuum)
      continuum->V = 0;
  }
} // namespace perideal
