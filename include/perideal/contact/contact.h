#pragma once
// Contact (doc/contact.md): the Contact section's interactions, the
// proximity search in the current configuration across ranks, its Verlet
// list, and the evaluation of the contact models over it.
//
// - Which pairs of blocks touch: General contact model (every two different
//   peridynamic blocks), Self contact model (points of one block that are
//   not bonded), and named Interactions (a pair of blocks, its own model),
//   which take precedence.
// - A pair of points interacts if it is not bonded by an intact bond: a bond
//   broken by damage counts as not bonded, checked at every evaluation.
// - The search radius is the largest contact radius plus a skin. The list
//   holds every pair within the search radius when it was built and is
//   rebuilt before an evaluation at which some point has moved more than
//   half the skin since (so no pair within a contact radius is ever missed),
//   or every Search frequency steps.
// - Across ranks: at every build each rank sends its points within the
//   search radius of another rank's current bounding box to that rank (the
//   contact ghosts), and their displacement and velocity travel every
//   evaluation through a Partitioner of their own.
// - Each rank evaluates the pairs of its own points and adds the force to
//   them only; the owner of the other point evaluates the same pair with the
//   same arithmetic (contact_model.h), so the forces are equal and opposite
//   to the bit and linear momentum is conserved to round-off.
//
// A scene without a Contact interaction allocates and computes none of this.

#include <perideal/base/input.h>
#include <perideal/contact/contact_model.h>
#include <perideal/material/material.h>
#include <perideal/model/block.h>
#include <perideal/neighborhood/bonds.h>

#include <deal.II/base/partitioner.h>
#include <deal.II/base/timer.h>

#include <array>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace perideal
{
  /// The Contact section and the Contact models section, as read.
  struct ContactParameters
  {
    std::map<std::string, std::unique_ptr<ContactModel>> models; // by name
    std::string general, self; // model names; empty: none
    struct Interaction
    {
      std::string name, first, second, model;
    };
    std::vector<Interaction> interactions;
    double                   search_radius    = 0; // 0: 1.5 x the largest contact radius
    unsigned int             search_frequency = 0; // 0: rebuild only when points have moved

    /// Whether any pair of blocks is in contact.
    bool
    active() const
    {
      return !general.empty() || !self.empty() || !interactions.empty();
    }

    /// Whether peridynamic block @p block takes part in some interaction:
    /// its points may then have no bonds at all (particles that interact
    /// only by contact).
    bool
    involves(const std::string &block) const
    {
      if (!general.empty() || !self.empty())
        return true;
      for (const auto &interaction : interactions)
        if (interaction.first == block || interaction.second == block)
          return true;
      return false;
    }

    static void
    declare_parameters(ParameterHandler &prm, const std::vector<std::string> &interaction_names);
    /// Reads the Contact section (the models are read by the deck) and checks
    /// every name against @p models and @p block_names.
    void
    parse_parameters(ParameterHandler &prm, const std::vector<std::string> &interaction_names,
                     const std::vector<std::string> &block_names);
  };

  class Contact
  {
  public:
    Contact(const ContactParameters &parameters, const std::vector<Block> &blocks, const PointCloud &cloud,
            const Bonds &bonds, const MPI_Comm comm, dealii::TimerOutput &timer);

    /// Which blocks interact (refuses continuum blocks and periodic scenes)
    /// and the constant per-point data; @p mass_density per owned point.
    void
    setup(const std::vector<double> &mass_density, const double point_spacing);

    /// Adds the contact force density of the current state to @p force (dim
    /// per owned point); @p u and @p v owned values, @p broken the bond
    /// damage (nullptr without), @p broken_version a count that changes
    /// whenever a bond of this rank breaks (the bonded pairs of the list are
    /// looked at again only then). Rebuilds the list when needed. Collective.
    void
    add_forces(const VectorType &u, const VectorType &v, const std::uint8_t *broken, const std::size_t broken_version,
               double *force, const double time, const double dt);

    /// The largest explicit step the contact springs allow at @p time: the
    /// Gershgorin bound with every neighbor volume of a ball of the contact
    /// radius plus a cell around each point. Collective.
    double
    stable_time_step(const double time) const;

    /// Of the last add_forces(), this rank's share: the contact springs'
    /// energy, and the power of friction (<= 0).
    double energy = 0, friction_power = 0;

    /// Builds of the list so far, its pairs now (this rank), contact ghosts now.
    unsigned int builds = 0;
    std::size_t  n_pairs() const;
    std::size_t  n_ghosts() const
    {
      return ghost_gid.size();
    }
    double
    search_radius() const
    {
      return radius;
    }
    /// The largest step of a point relative to the contact radius at the
    /// last evaluation (|v| dt / r_c), over all ranks; set by add_forces().
    double largest_step_fraction = 0;
    /// The point that first moved more than half a contact radius per step
    /// (BestPoint::describe()), or empty.
    std::string fastest_description;
    /// What setup() found suspicious but legal, for the run's warnings.
    std::vector<std::string> setup_warnings;

  private:
    /// setup_warnings: a contact radius beyond the horizon of a block in contact.
    void
    warn_radius_beyond_horizon();

    /// The contact ghosts and the Verlet list at the current positions. Collective.
    void
    build(const VectorType &u);
    /// build()'s steps. The contact ghosts of this build, after the owned
    /// points' data; returns the previous build's ghosts. Collective.
    std::vector<dealii::types::global_dof_index>
    gather_contact_ghosts(const double *U);
    /// The current bounding box of this rank's points in contact: lower
    /// corner, then upper.
    std::array<double, 2 * dim>
    bounding_box(const double *U) const;
    /// The records (gid, X, volume, mass, horizon, block) of this rank's
    /// points in contact within the search radius of @p box.
    std::vector<double>
    ghost_records_near(const std::array<double, 2 * dim> &box, const double *U) const;
    /// The partitioners of uv (and counts) for the contact ghosts.
    void
    make_partitioners();
    /// The current positions of the owned points and the contact ghosts.
    std::vector<double>
    current_positions(const double *U);
    struct CellList;
    /// The points in contact, binned at their current positions @p y.
    CellList
    sort_into_cells(const std::vector<double> &y) const;
    /// Into @p found: the points within the search radius of owned point
    /// @p i whose blocks are in contact with i's.
    void
    points_within(unsigned int i, const std::vector<double> &y, const CellList &cells,
                  std::vector<unsigned int> &found) const;
    /// The Verlet lists, unbonded and bonded pairs, of every owned point in
    /// contact; at the first build, refuses unbonded points in one place.
    void
    find_pairs(const std::vector<double> &y, const CellList &cells);

    const ContactParameters &parameters;
    const std::vector<Block> &blocks;
    const PointCloud         &cloud;
    const Bonds              &bonds;
    MPI_Comm                  comm;
    dealii::TimerOutput      &timer;

    std::vector<const ContactModel *> models;     // by model index
    std::vector<int>                  model_of;   // blocks x blocks: model index, -1 no contact
    std::vector<std::uint8_t>         takes_part; // per block
    double                            radius = 0, skin = 0, largest_contact_radius = 0, spacing = 0;
    unsigned int                      steps_since_build = 0;
    bool                              built             = false;

    // Per contact-local point (owned first, then contact ghosts): reference
    // position, volume, mass, horizon, block; ghosts refreshed at every build.
    std::vector<double>         X, volume, mass, horizon;
    std::vector<unsigned short> block;
    std::vector<std::uint8_t>   active; // per owned point: takes part (mass > 0, block in some interaction)
    std::vector<dealii::types::global_dof_index> ghost_gid;
    // u, and v if some model uses it, per point, ghosted: stride entries per point.
    unsigned int                                               stride = 2 * dim;
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> partitioner;
    VectorType                                                 uv;
    // With friction only: contacts per point now, ghosted (ContactPoints::contacts).
    bool                                                       counts_needed = false;
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> count_partitioner;
    VectorType                                                 counts;
    std::vector<double>                                        u_at_build;  // dim per owned point

    // The Verlet list per model: pairs never bonded, and pairs bonded at
    // set-up (they interact once the bond is broken), with the bond.
    struct PairList
    {
      std::vector<unsigned int> first, second;             // unbonded
      std::vector<unsigned int> bonded_first, bonded_second; // bonded
      std::vector<std::size_t>  bond;
      std::vector<unsigned int> broken_first, broken_second; // the bonded pairs broken now
    };
    // The broken_version the bonded pairs were last looked at for; none
    // since the last build: the largest value.
    std::size_t scanned_version = std::numeric_limits<std::size_t>::max();
    /// Adds to counts the pairs of @p first, @p second within @p radius.
    void
    count_contacts(const unsigned int *first, const unsigned int *second, const std::size_t n, const double radius);
    std::vector<PairList> lists;
  };
} // namespace perideal
