// Prototype microelastic brittle material (bond based; Peridigm's "Elastic
// Bond Based"). Pairwise force density on point i from bond i-j:
//   f = c s (1 - d) V_j M,   s = (|y_j - y_i| - |xi|) / |xi|,
//   c = 18 K / (pi delta^4),  M = (y_j - y_i) / |y_j - y_i|,
// Thermal strain: with the free thermal strain eps_T = alpha dT per point
// (ModelState::thermal_strain, dT = T - T_ref, alpha of the point's own
// material), the bond's stretch is the mechanical one, s = (|y| - |xi|)/|xi|
// - (eps_T,i + eps_T,j)/2 (the same for both ends, also across blocks of
// different alpha), in the force, the energy and the tangent.
// d the bond damage: 0 or 1 (binary damage models), or in [0, 1] (continuous
// ones; the energy and the tangent scale by 1 - d too: the secant at fixed d).
// Poisson's ratio is 1/4 by construction, so G = 3K/5: the moduli are one of
// K, E, G (elastic_constants.h), or two of the four keys implying nu = 1/4.
// Across blocks with different micromoduli the bond uses (c_i + c_j)/2, so
// action equals reaction. Across different horizons a bond may be in one
// family only (Bonds::family): each end contributes its half where the bond
// is in its family, c = (h_i c_i + h_j c_j)/2, h = 1 if in that family; both
// ends see the same c, so the bond still acts on both. With partial volumes
// V_j is beta_ij V_j.
// Surface correction (optional): a point whose family is cut by a free
// surface (or whose lattice sum misses the sphere's integral) is too soft.
// The energy method of Le & Bobaru (Comput. Mech. 61, 2018) with an
// isotropic expansion eps as the test field: the point's energy density is
// 1/4 c eps^2 sum_j |xi_ij| V_j, the continuum's 9/2 K eps^2 = 1/4 c eps^2
// pi delta^4, so c_i is scaled by g_i = pi delta^4 / sum_j |xi_ij| V_j and the
// bond takes (c_i + c_j)/2 as across blocks.
// The force loop evaluates a bond between two points of the block on the
// rank once and adds it to both ends (pair_kernel(); doc/performance.md,
// "Each pair once"); partial volumes and half bonds keep the directed loop.

#include <perideal/material/elastic_constants.h>
#include <perideal/material/material.h>
#include <perideal/neighborhood/bond_pairs.h>

#include <cmath>
#include <cstring>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class PMB : public Material
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Density", "0", Patterns::Double(), "Mass density rho.");
        declare_elastic_constants(prm);
        declare_thermal_expansion(prm);
        prm.declare_entry("Surface correction", "None", Patterns::Selection("None|Energy"),
                          "Energy: scale each point's micromodulus by g = pi delta^4 / sum_j |xi| V_j, the "
                          "continuum's over its family's strain energy density under an isotropic expansion "
                          "(Le & Bobaru 2018's energy method): restores the stiffness a free surface cuts "
                          "from a family for that field, and the lattice sum's quadrature error. Other fields "
                          "are not exact: a plate 4 points thick (horizon 4 h) becomes 22% too stiff under "
                          "uniaxial strain in its plane and 25% in shear (31% and 29% too soft without; "
                          "doc/models.md). Bonds use (c_i + c_j)/2. The set-up cost is one pass over the "
                          "bonds.");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path) override
      {
        rho = prm.get_double("Density");
        K   = parse_bond_based_elastic_constants(prm, path).K;
        thermal_expansion  = parse_thermal_expansion(prm, path);
        surface_correction = prm.get("Surface correction") == "Energy";
        require_positive(rho, path + "/Density");
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
        return thermal_expansion;
      }
      double
      shear_modulus() const override
      {
        return 0.6 * K;
      }

      double
      micromodulus() const
      {
        return 18 * K / (M_PI * std::pow(horizon, 4));
      }

      void
      initialize(const ModelState &state, const std::vector<unsigned int> &points) override
      {
        // The neighbourhoods change with a rebuild (a conversion): decide again.
        uniform_known = false;
        // Partial volumes and half bonds (mixed horizons) keep directed
        // families: their two halves need not weigh the same.
        if (state.bonds.volume_fraction.empty() && state.bonds.family.empty())
          pairs.reinit(state.cloud, state.bonds, points, block);
        else
          pairs.clear();
        VectorType &c = state.fields.get("pmb_micromodulus");
        for (const unsigned int i : points)
          c.local_element(i) = micromodulus();
        if (!surface_correction)
          return;
        for (const unsigned int i : points)
          {
            // Over the point's own family.
            const double sum = family_sum(state, i, [&](std::size_t b, unsigned int, const double r0, const double Vj) {
              return state.bonds.own(b) * r0 * Vj;
            });
            if (sum > 0)
              c.local_element(i) *= M_PI * std::pow(horizon, 4) / sum;
          }
      }

      std::vector<PointField>
      point_fields() const override
      {
        return {{"pmb_micromodulus", FieldUse::constant}};
      }

      void
      compute_force(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        const VectorType &c_field = state.fields.get("pmb_micromodulus");
        // One micromodulus in the whole family (the common case): the plain loop.
        const bool uniform = uniform_neighborhood(state, points, c_field);
        // Compile-time variants keep the bond loop free of branches.
        with_flag(thermal(state), [&](auto heated) {
          constexpr bool T = decltype(heated)::value;
          if (state.breaking && state.breaking->by_block())
            dispatch<BondDamage::breaking_by_block, T>(uniform, state, points, c_field);
          else if (state.breaking)
            dispatch<BondDamage::breaking, T>(uniform, state, points, c_field);
          else if (state.damage)
            dispatch<BondDamage::continuous, T>(uniform, state, points, c_field);
          else if (state.broken)
            dispatch<BondDamage::read, T>(uniform, state, points, c_field);
          else
            dispatch<BondDamage::none, T>(uniform, state, points, c_field);
        });
      }

      bool
      fuses_stretch_criterion() const override
      {
        return true;
      }

      bool
      fuses_limits_by_block() const override
      {
        return true;
      }

      bool
      has_bond_energy() const override
      {
        return true;
      }

      /// w = c s^2 |xi| / 2 (1 - d): the bond's micropotential, the work of its
      /// force c s along its extension s |xi| (doc/models.md).
      void
      bond_energies(const ModelState &state, const unsigned int i, double *w) const override
      {
        with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
          with_flag(thermal(state), [&](auto heated) {
            with_flag(!state.bonds.family.empty(), [&](auto halves) {
              constexpr bool P = decltype(periodic)::value, T = decltype(heated)::value, H = decltype(halves)::value;
              if (state.damage)
                energy_kernel<P, T, H, BondDamage::continuous>(state, i, w);
              else if (state.broken)
                energy_kernel<P, T, H, BondDamage::read>(state, i, w);
              else
                energy_kernel<P, T, H, BondDamage::none>(state, i, w);
            });
          });
        });
      }

      bool
      supports_continuous_damage() const override
      {
        return true;
      }

      /// A point's energy is a sum over its bonds: only the changed ones
      /// are visited, each with the share its weight lost, (1 - d) before
      /// minus now, of its energy c s^2 |xi| V_j / 4 (as kernel()).
      double
      released_energy(const ModelState &before, const ModelState &now, const std::vector<unsigned int> &points) const override
      {
        double e = 0;
        with_flag(now.cloud.periodicity.any(),
                  [&](auto P) { e = released<decltype(P)::value>(before, now, points); });
        return e;
      }

      bool
      weight_energy(const ModelState &state, const std::vector<unsigned int> &points, const double *weight) override
      {
        // A bond's energy goes with c_ij = (c_i + c_j)/2, half to each end:
        // scaling c_i by w_i weights the energy of point i by w_i.
        VectorType &c = state.fields.get("pmb_micromodulus");
        for (const unsigned int i : points)
          c.local_element(i) *= weight[i];
        uniform_known = false;
        return true;
      }

      double
      stable_time_step(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        // Silling-Askari: dt_i = sqrt(2 rho / sum_j V_j c_ij / |xi_ij|), the
        // Gershgorin bound of the bond-based tangent.
        const VectorType &c  = state.fields.get("pmb_micromodulus");
        double            dt = std::numeric_limits<double>::max();
        for (const unsigned int i : points)
          {
            const double sum = family_sum(state, i, [&](std::size_t b, const unsigned int j, const double r0, const double Vj) {
              return Vj * bond_micromodulus(state.bonds, b, c.local_element(i), c.local_element(j)) / r0;
            });
            if (sum > 0)
              dt = std::min(dt, std::sqrt(2 * rho / sum));
          }
        return dt;
      }

      unsigned int
      coupling_hops() const override
      {
        return 1;
      }

      bool
      add_tangent(const ModelState &state, const std::vector<unsigned int> &points, TangentRows &rows) const override
      {
        // Row i of K = -d(V_i f_i)/du: with M = y/|y|, s the stretch,
        //   d(s M)/dy = M M^T / |xi| + s (I - M M^T) / |y|,
        // A_ij = c (1 - d) V_j d(s M)/dy; K_ij = -V_i A_ij, K_ii = V_i sum_j A_ij.
        const VectorType  &c = state.fields.get("pmb_micromodulus");
        const double      *V = state.cloud.volume.data();
        const double      *u = state.u;
        std::vector<unsigned int> cols;
        std::vector<double>       blocks;
        for (const unsigned int i : points)
          {
            const std::size_t first = state.bonds.offsets[i], n = state.bonds.offsets[i + 1] - first;
            cols.resize(n + 1);
            blocks.assign(9 * (n + 1), 0.0);
            cols[0] = i;
            for (std::size_t k = 0; k < n; ++k)
              {
                const std::size_t  b = first + k;
                const unsigned int j = state.bonds.neighbor[b];
                cols[k + 1]          = j;
                // Continuous damage: the secant stiffness (1 - d) at fixed d.
                const double intact = state.damage ? 1 - state.damage[b] : state.broken ? 1 - state.broken[b] : 1;
                if (intact == 0)
                  continue;
                double xi[3], y[3];
                const auto [r0, r] = bond_geometry(state.cloud, u, i, j, xi, y);
                const double cv = intact * bond_micromodulus(state.bonds, b, c.local_element(i), c.local_element(j)) *
                                  V[j] * state.bonds.fraction(b) * V[i];
                add_pair_bond_tangent(blocks.data(), k, cv, y, r0, r, thermal_stretch(state, i, j));
              }
            rows.add(i, cols.data(), blocks.data(), n + 1);
          }
        return true;
      }

    private:
      template <bool periodic>
      double
      released(const ModelState &before, const ModelState &now, const std::vector<unsigned int> &points) const
      {
        const Periodicity   box      = now.cloud.periodicity;
        const double       *X        = now.cloud.X.data();
        const double       *V        = now.cloud.volume.data();
        const double       *u        = now.u;
        const unsigned int *neighbor = now.bonds.neighbor.data();
        const double       *c        = now.fields.get("pmb_micromodulus").begin();
        const float        *fraction = now.bonds.volume_fraction.empty() ? nullptr : now.bonds.volume_fraction.data();
        const std::uint8_t *family   = now.bonds.family.empty() ? nullptr : now.bonds.family.data();
        const double       *eps_T    = now.thermal_strain;
        double              released = 0;
        for (const unsigned int i : points)
          {
            const BondOrigin origin(X, u, i);
            double           sum = 0;
            const std::size_t last = now.bonds.offsets[i + 1];
            for (std::size_t b = now.bonds.offsets[i]; b < last; ++b)
              {
                // Binary damage: most bonds are unchanged; skip them eight at a time.
                if (!now.damage && b + 8 <= last)
                  {
                    std::uint64_t eight_now, eight_before;
                    std::memcpy(&eight_now, now.broken + b, 8);
                    std::memcpy(&eight_before, before.broken + b, 8);
                    if (eight_now == eight_before)
                      {
                        b += 7;
                        continue;
                      }
                  }
                const double lost = now.damage ? now.damage[b] - before.damage[b] : double(now.broken[b]) - before.broken[b];
                if (lost == 0)
                  continue;
                const unsigned int j = neighbor[b];
                double             e[3], y[3];
                bond_vectors<periodic>(X, u, j, origin, box, e, y);
                const double r0  = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
                const double r   = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
                const double s   = eps_T ? (r - r0) / r0 - 0.5 * (eps_T[i] + eps_T[j]) : (r - r0) / r0;
                const double cij = family ? 0.5 * ((family[b] & Bonds::own_half ? c[i] : 0.0) +
                                                   (family[b] & Bonds::other_half ? c[j] : 0.0)) :
                                            0.5 * (c[i] + c[j]);
                const double Vj  = fraction ? fraction[b] * V[j] : V[j];
                sum += lost * 0.25 * cij * s * s * r0 * Vj;
              }
            released += V[i] * sum;
          }
        return released;
      }

      double rho = 0, K = 0, thermal_expansion = 0;
      bool   surface_correction = false;

      bool
      thermal(const ModelState &state) const
      {
        return state.thermal_strain != nullptr;
      }
      /// The free thermal stretch of bond i-j, the mean of its ends' (set-up and tangent).
      double
      thermal_stretch(const ModelState &state, const unsigned int i, const unsigned int j) const
      {
        return thermal(state) ? 0.5 * (state.thermal_strain[i] + state.thermal_strain[j]) : 0.0;
      }

      /// sum over the bonds b = i->j of owned point @p i of f(b, j, |xi_ij|,
      /// beta_ij V_j) (set-up loops).
      template <typename Function>
      static double
      family_sum(const ModelState &state, const unsigned int i, const Function &f)
      {
        double sum = 0;
        for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
          {
            const unsigned int j = state.bonds.neighbor[b];
            sum += f(b, j, state.cloud.bond_vector(i, j).norm(), state.cloud.volume[j] * state.bonds.fraction(b));
          }
        return sum;
      }

      /// c of bond @p b between micromoduli @p ci and @p cj: each end's half
      /// where the bond is in its family (set-up and tangent).
      static double
      bond_micromodulus(const Bonds &bonds, const std::size_t b, const double ci, const double cj)
      {
        if (bonds.family.empty())
          return 0.5 * (ci + cj);
        const std::uint8_t h = bonds.family[b];
        return 0.5 * ((h & Bonds::own_half ? ci : 0.0) + (h & Bonds::other_half ? cj : 0.0));
      }

      bool
      uniform_neighborhood(const ModelState                &state,
                           const std::vector<unsigned int> &points,
                           const VectorType                &c) const
      {
        // Decided once: the field is constant after set-up.
        if (uniform_known)
          return uniform;
        uniform = true;
        for (const unsigned int i : points)
          for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
            if (c.local_element(state.bonds.neighbor[b]) != micromodulus())
              uniform = false;
        uniform_known = true;
        return uniform;
      }
      mutable bool uniform = true, uniform_known = false;

      template <BondDamage mode, bool T>
      void
      dispatch(const bool uniform, const ModelState &state, const std::vector<unsigned int> &points, const VectorType &c) const
      {
        with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
          constexpr bool P = decltype(periodic)::value;
          if (!state.bonds.volume_fraction.empty())
            state.energy ? kernel<false, mode, true, true, P, T>(state, points, c) :
                           kernel<false, mode, false, true, P, T>(state, points, c);
          else if (!state.bonds.family.empty())
            state.energy ? kernel<false, mode, true, false, P, T, true>(state, points, c) :
                           kernel<false, mode, false, false, P, T, true>(state, points, c);
          else if (uniform)
            state.energy ? kernel<true, mode, true, false, P, T>(state, points, c) :
                           kernel<true, mode, false, false, P, T>(state, points, c);
          else
            state.energy ? kernel<false, mode, true, false, P, T>(state, points, c) :
                           kernel<false, mode, false, false, P, T>(state, points, c);
        });
      }

      /// bond_energies() of point @p i, as kernel() computes the stretch and c.
      template <bool periodic, bool heated, bool halves, BondDamage mode>
      void
      energy_kernel(const ModelState &state, const unsigned int i, double *w) const
      {
        const Periodicity   box      = state.cloud.periodicity;
        const double       *X        = state.cloud.X.data();
        const double       *u        = state.u;
        const unsigned int *neighbor = state.bonds.neighbor.data();
        const double       *c        = state.fields.get("pmb_micromodulus").begin();
        const std::uint8_t *family   = state.bonds.family.data(); // halves only
        const double       *d        = state.damage;
        const std::uint8_t *broken   = state.broken;
        const double       *eps_T    = state.thermal_strain; // heated only
        const std::size_t   first    = state.bonds.offsets[i], last = state.bonds.offsets[i + 1];
        const BondOrigin    origin(X, u, i);
  #pragma omp simd
        for (std::size_t b = first; b < last; ++b)
          {
            const unsigned int j = neighbor[b];
            double             e[3], y[3];
            bond_vectors<periodic>(X, u, j, origin, box, e, y);
            const double r0  = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
            const double r   = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
            const double s   = heated ? (r - r0) / r0 - 0.5 * (eps_T[i] + eps_T[j]) : (r - r0) / r0;
            const double cij = halves ? 0.5 * ((family[b] & Bonds::own_half ? c[i] : 0.0) +
                                               (family[b] & Bonds::other_half ? c[j] : 0.0)) :
                                        0.5 * (c[i] + c[j]);
            const double intact = mode == BondDamage::none       ? 1.0 :
                                  mode == BondDamage::continuous ? 1.0 - d[b] :
                                                                   1.0 - broken[b];
            w[b - first] = intact * 0.5 * cij * s * s * r0;
          }
      }

      /// halves: blocks of different horizons (Bonds::family), never with
      /// partial volumes (their bonds are in both families).
      template <bool uniform_c, BondDamage mode, bool energy, bool partial, bool periodic, bool heated, bool halves = false>
      void
      kernel(const ModelState &state, const std::vector<unsigned int> &points, const VectorType &c_field) const
      {
        if constexpr (!partial && !halves)
          if (pairs.serves(points))
            {
              pair_kernel<uniform_c, mode, energy, periodic, heated>(state, points, c_field);
              return;
            }
        const Periodicity   box      = state.cloud.periodicity;
        const double       *X        = state.cloud.X.data();
        const double       *V        = state.cloud.volume.data();
        const double       *u        = state.u;
        const std::size_t  *offsets  = state.bonds.offsets.data();
        const unsigned int *neighbor = state.bonds.neighbor.data();
        // Breaking writes bond damage; reading only needs the const view.
        constexpr bool by_block = mode == BondDamage::breaking_by_block;
        const auto [broken, damage, limit, limit_at] = bond_damage_view<mode>(state);
        const double       *d      = state.damage; // continuous only
        const double       *c      = c_field.begin();
        const double        c_own  = micromodulus();
        const float        *beta   = state.bonds.volume_fraction.data();
        const std::uint8_t *family = state.bonds.family.data();
        double             *f      = state.force;
        const double       *eps_T  = state.thermal_strain; // heated only
        std::size_t         newly_broken = 0;

        for (const unsigned int i : points)
          {
            const BondOrigin origin(X, u, i);
            double           fx = 0, fy = 0, fz = 0, w = 0;
  #pragma omp simd reduction(+ : fx, fy, fz, w, newly_broken)
            for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
              {
                const unsigned int j = neighbor[b];
                double             e[3], y[3];
                bond_vectors<periodic>(X, u, j, origin, box, e, y);
                const double ex = e[0], ey = e[1], ez = e[2], dx = y[0], dy = y[1], dz = y[2];
                const double       r0sq = ex * ex + ey * ey + ez * ez;
                const double       rsq  = dx * dx + dy * dy + dz * dz;
                if (breaks(mode))
                  newly_broken += break_if_overstretched(rsq, r0sq, by_block ? limit_at[j] : limit, broken[b]);
                const double r0     = std::sqrt(r0sq);
                const double r      = std::sqrt(rsq);
                const double s      = heated ? (r - r0) / r0 - 0.5 * (eps_T[i] + eps_T[j]) : (r - r0) / r0;
                const double cij    = uniform_c ? c_own :
                                      halves    ? 0.5 * ((family[b] & Bonds::own_half ? c[i] : 0.0) +
                                                      (family[b] & Bonds::other_half ? c[j] : 0.0)) :
                                                  0.5 * (c[i] + c[j]);
                const double intact = mode == BondDamage::none       ? 1.0 :
                                      mode == BondDamage::continuous ? 1.0 - d[b] :
                                                                       1.0 - damage[b];
                const double Vj     = partial ? beta[b] * V[j] : V[j];
                const double k      = intact * cij * s * Vj / r;
                fx += k * dx;
                fy += k * dy;
                fz += k * dz;
                if (energy)
                  w += intact * 0.25 * cij * s * s * r0 * Vj;
              }
            f[3 * i] += fx;
            f[3 * i + 1] += fy;
            f[3 * i + 2] += fz;
            if (energy)
              state.energy[i] += w;
          }
        if (breaks(mode))
          state.breaking->newly_broken += newly_broken;
      }

      /// kernel() with each bond between two points of the list evaluated
      /// once (BondPairs): at the end with the smaller key, its force k y
      /// per unit volume added to i with V_j and taken from j with V_i, its
      /// energy to both alike. A family that reaches outside the list takes
      /// its bonds with a mask (PairPart).
      template <bool uniform_c, BondDamage mode, bool energy, bool periodic, bool heated>
      void
      pair_kernel(const ModelState &state, const std::vector<unsigned int> &points, const VectorType &c_field) const
      {
        const PairData data{pair_loop_data<mode>(state, pairs), c_field.begin(), micromodulus(), state.energy};
        const std::size_t newly_broken =
          pairs.for_each_part(state.cloud, state.bonds, points, data.broken, [&](auto part, auto... range) {
            return pair_loop<decltype(part)::value, uniform_c, mode, energy, periodic, heated>(data, range...);
          });
        if (breaks(mode))
          state.breaking->newly_broken += newly_broken;
      }

      /// What pair_loop() reads besides PairLoopData, taken once per kernel
      /// call.
      struct PairData : PairLoopData
      {
        const double *c;
        double        c_own;
        double       *energy_density;
      };

      /// The bonds [from, last) of point i, which are the @p part of its
      /// family; returns the halves newly broken (two for a bond evaluated for
      /// both ends).
      template <PairPart part, bool uniform_c, BondDamage mode, bool energy, bool periodic, bool heated>
      static std::size_t
      pair_loop(const PairData &p, const unsigned int i, const std::size_t from, const std::size_t last)
      {
        constexpr bool masked = pair_masked(part), scatter = pair_scatters(part);
        constexpr bool      by_block = mode == BondDamage::breaking_by_block;
        const double       *X = p.X, *V = p.V, *u = p.u, *c = p.c, *d = p.d, *eps_T = p.eps_T, *limit_at = p.limit_at;
        const unsigned int *neighbor = p.neighbor;
        const std::uint8_t *damage   = p.damage;
        std::uint8_t       *broken   = p.broken;
        double             *f = p.f, *energy_density = p.energy_density;
        const BondOrigin    origin(X, u, i);
        const double        Vi = V[i];
        double              fx = 0, fy = 0, fz = 0, w = 0;
        std::size_t         newly = 0;
        // Vectorized over the bonds with gathers of the far ends' data and
        // scatters of their forces: no two bonds of a family share a far end,
        // and a masked bond writes +0 to point i's own entry.
  #pragma omp simd reduction(+ : fx, fy, fz, w, newly)
        for (std::size_t b = from; b < last; ++b)
          {
            const unsigned int j = neighbor[b];
            // The share of the bond's force each end takes: 1 or 0.
            unsigned int on_i, on_j;
            pair_shares<part>(masked && p.listed(j), on_i, on_j);
            double e[3], y[3];
            bond_vectors<periodic>(X, u, j, origin, p.box, e, y);
            const double ex = e[0], ey = e[1], ez = e[2], dx = y[0], dy = y[1], dz = y[2];
            const double r0sq = ex * ex + ey * ey + ez * ez;
            const double rsq  = dx * dx + dy * dy + dz * dz;
            // Both ends decide alike (the same squares, bit for bit), so a
            // head bond may break here too: its halves are counted where it
            // is evaluated.
            if (breaks(mode))
              newly += (on_i + on_j) * break_if_overstretched(rsq, r0sq, by_block ? limit_at[j] : p.limit, broken[b]);
            const double r0     = std::sqrt(r0sq);
            const double r      = std::sqrt(rsq);
            const double s      = heated ? (r - r0) / r0 - 0.5 * (eps_T[i] + eps_T[j]) : (r - r0) / r0;
            const double cij    = uniform_c ? p.c_own : 0.5 * (c[i] + c[j]);
            const double intact = mode == BondDamage::none       ? 1.0 :
                                  mode == BondDamage::continuous ? 1.0 - d[b] :
                                                                   1.0 - damage[b];
            const double kb     = intact * cij * s / r;
            const PairSplit k = split_pair<masked>(kb, Vi, V[j], i, j, on_i, on_j);
            fx += k.on_i * dx;
            fy += k.on_i * dy;
            fz += k.on_i * dz;
            if constexpr (scatter)
              scatter_pair_force(f, k.target, k.on_j, dx, dy, dz);
            if (energy)
              {
                const PairSplit wb = split_pair<masked>(intact * 0.25 * cij * s * s * r0, Vi, V[j], i, j, on_i, on_j);
                w += wb.on_i;
                if constexpr (scatter)
                  energy_density[wb.target] += wb.on_j;
              }
          }
        f[3 * i] += fx;
        f[3 * i + 1] += fy;
        f[3 * i + 2] += fz;
        if (energy)
          energy_density[i] += w;
        return newly;
      }

      BondPairs pairs;
    };
  } // namespace

  PERIDEAL_REGISTER(Material, PMB, "PMB",
                    "Prototype microelastic brittle, bond based (Peridigm's 'Elastic "
                    "Bond Based'). Keys: Density, one of Bulk modulus, Young's modulus, Shear modulus (Poisson's "
                    "ratio 1/4), Thermal expansion coefficient, Surface correction.")
} // namespace perideal
