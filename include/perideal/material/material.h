#pragma once
// The Material interface: force density on the owned points of one block.
//
// A material is serial code over flat arrays; it never calls MPI. The state it
// keeps beyond the displacement it declares in point_fields() and
// bond_fields() (field_store.h): constant fields filled in initialize(),
// stage fields that compute_stage() fills and the core ghosts before
// compute_force() (a neighbor's derived value, as LPS's dilatation terms),
// local results, and history with N and NP1 copies that the integrators
// commit once per accepted step. A field with an output name is one of
// Output/Variables.
//
// A new model is one file in source/material/ with PERIDEAL_REGISTER(Material,
// ClassName, "Name", "documentation") at its bottom; nothing else changes.

#include <perideal/base/input.h>
#include <perideal/discretization/point_cloud.h>
#include <perideal/material/field_store.h>
#include <perideal/neighborhood/bond_pairs.h>
#include <perideal/neighborhood/bonds.h>
#include <perideal/material/tangent_rows.h>

#include <deal.II/lac/la_parallel_vector.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <type_traits>
#include <utility>
#include <string>
#include <vector>

namespace perideal
{
  /// Bond breaking by a stretch criterion, done inside a material's first bond
  /// pass instead of a separate pass over all bonds (see Material::
  /// fuses_stretch_criterion()). Bond b of point i breaks for good when
  /// |y_j - y_i|^2 > squared_limit |xi|^2, before the material uses it.
  /// Where the block's bonds do not share one limit (they reach blocks of
  /// other critical stretches, e.g. a continuum block's virtual points beside
  /// a PD block), the limit is by the far end: limit_at[j] (+infinity: never),
  /// for a material that fuses_limits_by_block(). By point, not by block
  /// number: one gather per bond, which the bond loop vectorizes.
  struct StretchBreaking
  {
    double        squared_limit = 0; // (1 + s_c)^2; 0: by the far end, limit_at
    const double *limit_at      = nullptr;
    std::uint8_t *broken        = nullptr;
    std::size_t   newly_broken  = 0; // bonds this evaluation broke

    /// True if the limit is by the far end's block.
    bool
    by_block() const
    {
      return squared_limit == 0;
    }
  };

  /// The bond-break test of StretchBreaking for one bond, from its squared
  /// deformed and reference lengths: breaks it for good if y_sq >
  /// squared_limit xi_sq and returns 1 if it broke now. Every pass that applies
  /// a critical stretch (the damage model's own, or fused into a material's
  /// bond loop) uses this one definition, so they decide alike bit for bit.
  inline std::uint8_t
  break_if_overstretched(const double y_sq, const double xi_sq, const double squared_limit, std::uint8_t &broken)
  {
    const std::uint8_t breaks = y_sq > squared_limit * xi_sq;
    const std::uint8_t newly  = breaks & (1 - broken);
    broken |= breaks;
    return newly;
  }

  /// Bond i->j: xi = X_j - X_i (its minimum image where periodic) and
  /// y = xi + u_j - u_i; returns {|xi|, |y|}. For set-up and tangents; the
  /// force loops keep their own fused arithmetic.
  inline std::pair<double, double>
  bond_geometry(const PointCloud &cloud, const double *u, const unsigned int i, const unsigned int j, double *xi,
                double *y)
  {
    const double *X = cloud.X.data();
    for (unsigned int d = 0; d < 3; ++d)
      xi[d] = X[3 * j + d] - X[3 * i + d];
    if (cloud.periodicity.any())
      cloud.periodicity.wrap(xi[0], xi[1], xi[2]);
    for (unsigned int d = 0; d < 3; ++d)
      y[d] = xi[d] + u[3 * j + d] - u[3 * i + d];
    return {std::sqrt(xi[0] * xi[0] + xi[1] * xi[1] + xi[2] * xi[2]), std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2])};
  }

  /// The tangent of a pair (bond-based) force cv s M on bond k of a point's
  /// family (M = y/|y|, s = |y|/|xi| - 1, cv: the micromodulus times the
  /// volumes and the bond's intact share): A = cv d(s M)/dy = cv (M M^T / |xi|
  /// + s (I - M M^T) / |y|) is added to the owner's block 0 and subtracted
  /// from block k + 1 of the row's 3x3 blocks (TangentRows::add()).
  /// @p thermal_stretch: the bond's free thermal stretch alpha dT_ij, taken
  /// off s (thermal strain).
  inline void
  add_pair_bond_tangent(double *blocks, const std::size_t k, const double cv, const double (&y)[3], const double r0,
                        const double r, const double thermal_stretch = 0)
  {
    const double s = (r - r0) / r0 - thermal_stretch;
    for (unsigned int p = 0; p < 3; ++p)
      for (unsigned int q = 0; q < 3; ++q)
        {
          const double MM = y[p] * y[q] / (r * r);
          const double A  = cv * (MM / r0 + s * ((p == q) - MM) / r);
          blocks[9 * (k + 1) + 3 * p + q] = -A;
          blocks[3 * p + q] += A;
        }
  }

  /// The owner's side of a hot bond loop, hoisted out of the loop over its family.
  struct BondOrigin
  {
    double x[3], y[3], u[3]; // X_i, X_i + u_i, u_i

    BondOrigin(const double *X, const double *disp, const unsigned int i)
    {
      for (unsigned int d = 0; d < 3; ++d)
        {
          x[d] = X[3 * i + d];
          u[d] = disp[3 * i + d];
          y[d] = x[d] + u[d];
        }
    }
  };

  /// Bond i -> j in the hot loops: e = X_j - X_i and d = y_j - y_i, both
  /// exactly antisymmetric in floating point, so both owners of a bond see the
  /// same lengths. Open: d = (X_j + u_j) - (X_i + u_i). Periodic (a compile-time
  /// variant, so an open scene pays nothing): e is the minimum image and
  /// d = e + (u_j - u_i).
  template <bool periodic>
  inline void
  bond_vectors(const double *X, const double *u, const unsigned int j, const BondOrigin &o, const Periodicity &box,
               double (&e)[3], double (&d)[3])
  {
    // Scalar by scalar: passing e[k] by reference to the wrap keeps GCC from
    // vectorizing the bond loop.
    for (unsigned int k = 0; k < 3; ++k)
      {
        if constexpr (periodic)
          {
            e[k] = box.wrapped(X[3 * j + k] - o.x[k], k);
            d[k] = e[k] + (u[3 * j + k] - o.u[k]);
          }
        else
          {
            e[k] = X[3 * j + k] - o.x[k];
            d[k] = (X[3 * j + k] + u[3 * j + k]) - o.y[k];
          }
      }
  }

  /// Calls @p f with std::true_type or std::false_type: turns a run-time flag
  /// into a compile-time kernel variant.
  template <typename F>
  inline void
  with_flag(const bool flag, const F &f)
  {
    if (flag)
      f(std::true_type());
    else
      f(std::false_type());
  }

  /// What a material's bond loop does with bond damage: nothing (no damage
  /// model), read the binary flags, also apply StretchBreaking first (fused
  /// breaking), or read the continuous d (ModelState::damage). Compile-time
  /// variants: each kernel is generated for the scenes that need it.
  enum class BondDamage
  {
    none,
    read,
    breaking,
    breaking_by_block, // breaking, at the far end's block's limit (StretchBreaking::by_block())
    continuous
  };

  /// The per-bond damage a DamageModel updates.
  struct BondDamageArrays
  {
    std::uint8_t *broken;           // 1 = broken for good (d = 1)
    double       *damage = nullptr; // continuous models only: d, raised in place
  };

  /// What a material reads and writes in one evaluation.
  struct ModelState
  {
    const PointCloud   &cloud;
    const Bonds        &bonds;
    const std::uint8_t *broken; // 1 = broken, per bond; nullptr without damage
    const double       *u;      // displacement, dim per local point (owned + ghosts)
    double             *force;  // force density, dim per owned point (added to)
    double             *energy; // strain energy density per owned point, or nullptr
    FieldStore         &fields;
    StretchBreaking    *breaking = nullptr; // set only if the material fuses the check
    // Continuous bond damage d in [0, 1] per bond, set only for a block whose
    // damage model is continuous: the material scales bond b by 1 - damage[b]
    // and ignores broken (d = 1 there).
    const double *damage = nullptr;
    // The time the state belongs to and the step that led to it (0 at the
    // initial state): rate models (viscoelasticity) integrate their history
    // N -> NP1 over dt, time-dependent fields (a temperature) read time.
    double time = 0;
    double dt   = 0;
    // The free thermal strain alpha_i (T_i - T_ref) of each local point
    // (owned + ghosts), alpha_i that of point i's own material; nullptr when
    // the scene has no temperature field. A bond takes the mean of its two
    // ends', the same value for both owners, so action equals reaction also
    // between blocks of different thermal expansion coefficients.
    const double *thermal_strain = nullptr;
  };

  /// A bond loop's view of the bond damage for variant @p mode: the flags it
  /// writes (breaking) or reads, and the limit of a bond to point j: limit,
  /// or limit_at[j] for breaking_by_block (StretchBreaking). Taken into
  /// locals before the loop.
  struct BondDamageView
  {
    std::uint8_t       *broken   = nullptr; // written by a breaking variant
    const std::uint8_t *damage   = nullptr; // the flags read for 1 - d
    double              limit    = 0;
    const double       *limit_at = nullptr;
  };

  constexpr bool
  breaks(const BondDamage mode)
  {
    return mode == BondDamage::breaking || mode == BondDamage::breaking_by_block;
  }

  template <BondDamage mode>
  BondDamageView
  bond_damage_view(const ModelState &state)
  {
    if constexpr (breaks(mode))
      return {state.breaking->broken, state.breaking->broken, state.breaking->squared_limit,
              mode == BondDamage::breaking_by_block ? state.breaking->limit_at : nullptr};
    else
      return {nullptr, state.broken, 0.0, nullptr};
  }

  /// The part of a pair loop's data every model takes alike: the cloud,
  /// the bonds and @p mode's damage view of @p state, for @p pairs' list.
  template <BondDamage mode>
  PairLoopData
  pair_loop_data(const ModelState &state, const BondPairs &pairs)
  {
    const BondDamageView v = bond_damage_view<mode>(state);
    return {state.cloud.periodicity, state.cloud.X.data(), state.cloud.volume.data(), state.u,
            state.bonds.neighbor.data(), state.cloud.block.data(), v.broken, v.damage, v.limit, v.limit_at,
            state.damage, state.thermal_strain, state.force, pairs.n_owned, pairs.block};
  }

  class Material
  {
  public:
    virtual ~Material() = default;

    /// Called inside the material's subsection; @p path names it in errors.
    virtual void
    parse_parameters(ParameterHandler &prm, const std::string &path) = 0;

    /// The block this instance serves and its horizon.
    void
    set_block(const unsigned int block_, const double horizon_)
    {
      block   = block_;
      horizon = horizon_;
    }

    virtual double
    density() const = 0;
    virtual double
    bulk_modulus() const = 0;
    virtual double
    shear_modulus() const = 0;
    /// alpha of "Thermal expansion coefficient": the core multiplies the
    /// temperature change of the material's points by it
    /// (ModelState::thermal_strain). 0: the model has no thermal strain.
    virtual double
    thermal_expansion_coefficient() const
    {
      return 0;
    }

    /// Reference-state set-up (e.g. weighted volume) over the block's points.
    virtual void
    initialize(const ModelState &, const std::vector<unsigned int> &)
    {}
    /// The per-point fields this material uses (field_store.h), allocated by
    /// the core before initialize().
    virtual std::vector<PointField>
    point_fields() const
    {
      return {};
    }
    /// The per-bond history fields this material uses.
    virtual std::vector<BondField>
    bond_fields() const
    {
      return {};
    }

    /// The first pass of an evaluation: fills the stage (and local) fields
    /// compute_force() needs, ghosts then made current by the core.
    virtual void
    compute_stage(const ModelState &, const std::vector<unsigned int> &) const
    {}

    /// Adds the force density of every point in @p points to state.force
    /// and, if state.energy is set, writes its strain energy density. A
    /// point's energy density depends on its own family's bonds and stage
    /// fields alone (released_energy() evaluates only the points whose bonds
    /// broke).
    virtual void
    compute_force(const ModelState &state, const std::vector<unsigned int> &points) const = 0;

    /// The strain energy a change of bond damage released at @p points:
    /// sum_i V_i (W_i(before) - W_i(now)), the two states at the same
    /// displacement and differing only in their damage (ModelState::broken
    /// and ::damage). The default evaluates compute_stage() and
    /// compute_force() with the energy at @p before, then at @p now, into
    /// the states' force and energy arrays (scratch, written at @p points
    /// only), so that the stage fields of @p points end as now's. A material
    /// whose W_i is a closed function of sums over the bonds (PMB, LPS,
    /// Elastic plastic, Viscoelastic) overrides it with one pass over the
    /// points' bonds that writes nothing (Solver/Track dissipated energy then
    /// costs a few percent instead of two more evaluations of those points).
    virtual double
    released_energy(const ModelState &before, const ModelState &now, const std::vector<unsigned int> &points) const;

    /// True if bond_energies() gives the energy of each bond (a damage
    /// model by bond energy, Critical energy, needs it).
    virtual bool
    has_bond_energy() const
    {
      return false;
    }

    /// A damage model of this block breaks bonds by their energy
    /// (DamageModel::uses_bond_energy()). Called before point_fields() and
    /// bond_fields() are read: a material whose bond energy depends on the
    /// path (plastic, viscous) keeps the work done on each bond from now on,
    /// as per-bond history that only such a block pays for; has_bond_energy()
    /// is then true. A material whose bond energy is a function of the
    /// current state (PMB, LPS) needs nothing.
    virtual void
    request_bond_energy()
    {}

    /// The energy of each bond of point @p i into w[k], k = b - offsets[i]:
    /// the work 1/2 f . eta of the bond's pairwise force density f (both
    /// halves, per unit volume of each end) along the relative displacement
    /// eta (for a force along the bond, f e with e its mechanical
    /// extension), times 1 - d. For an elastic material whose energy is
    /// quadratic in the deformation, sum over the pairs of w beta V_i V_j
    /// (beta: the partial volume fraction, 1 without) is the strain energy,
    /// and w is the work the pair's force has done under
    /// proportional loading (doc/models.md derives it per family). A
    /// path-dependent material (request_bond_energy()) gives the work done on
    /// the bond so far, stored and dissipated, as its last evaluation
    /// integrated it. Reads the stage fields as the last evaluation left them
    /// (ghosts current); the same value on both owners of a bond.
    virtual void
    bond_energies(const ModelState &, const unsigned int, double *) const
    {}

    /// True if the material applies state.breaking in its first bond pass
    /// (compute_stage() if it has one, else compute_force()), with the test
    /// exactly as written in StretchBreaking. The core then skips the
    /// critical-stretch model's own pass over the bonds of this block.
    virtual bool
    fuses_stretch_criterion() const
    {
      return false;
    }

    /// True if the fused test also takes a limit by the far end's block
    /// (StretchBreaking::by_block()), so the core skips the separate pass for
    /// a block whose bonds break at different stretches too.
    virtual bool
    fuses_limits_by_block() const
    {
      return false;
    }

    /// True if the material scales each bond's force, energy and tangent by
    /// 1 - state.damage[b] when state.damage is set (BondDamage::continuous);
    /// a block with a continuous damage model needs it (refused at set-up
    /// otherwise).
    virtual bool
    supports_continuous_damage() const
    {
      return false;
    }

    /// The smallest stable explicit time step over @p points, from this
    /// material's own stiffness (a Gershgorin bound of its tangent).
    virtual double
    stable_time_step(const ModelState &state, const std::vector<unsigned int> &points) const = 0;

    /// How far the force of a point reaches, in bonds: 1 if it depends on
    /// its own family only (bond based), 2 if also on its neighbors'
    /// families (state based). The implicit solvers size the tangent's
    /// sparsity from it.
    virtual unsigned int
    coupling_hops() const
    {
      return 2;
    }

    /// Adds the analytic tangent of the points in @p points to @p K (-d(V_i
    /// f_i)/du in 3x3 blocks, TangentRows) for the state as compute_force()
    /// sees it (stage fields ghosted); rows of other points (neighbors, owned
    /// or ghost) only with columns of local points. Returns false if the
    /// material has no analytic tangent, also on no points (the solvers ask
    /// so at set-up, to name the tangent); they then use finite differences.
    virtual bool
    add_tangent(const ModelState &, const std::vector<unsigned int> &, TangentRows &) const
    {
      return false;
    }

    /// Weights the energy of each point: E = sum_i w_i V_i W_i, with
    /// @p weight indexed by local point (0 <= w_i <= 1), so that the force
    /// and the tangent become this energy's derivatives. Virtual points of a
    /// coupling with finite elements carry 0, a blending band values between
    /// (doc/coupling.md). Call after initialize() and before the constant
    /// fields are ghosted. Returns false if the material cannot be weighted.
    virtual bool
    weight_energy(const ModelState &, const std::vector<unsigned int> &, const double *)
    {
      return false;
    }

  protected:
    unsigned int block   = 0;
    double       horizon = 0;
  };

  /// Declares the "Model" key of a material subsection; the chosen model then
  /// declares its own keys beside it.
  void
  declare_material_model_entry(ParameterHandler &prm);
} // namespace perideal
