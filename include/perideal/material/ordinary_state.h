#pragma once
// What Mitchell's ordinary state-based models (Elastic plastic, Viscoelastic)
// share: LPS's structure with omega = 1 (times beta_ij with partial volumes),
// its constant per-point fields, their set-up, the Gershgorin bound of the
// elastic tangent (the stable time step), and the bond kinematics of the
// kernels. Each model keeps its constitutive update in its own file.
//   m_i = sum_j w |xi|^2 V_j,  kappa_i = 3K/m_i,  alpha_i = 15G/m_i,
//   D_i = |3K - 5G| A_i / m_i^2  (A_i = sum_j w |xi| V_j; the coupling to the
//   neighbors' dilatations in the Gershgorin bound, as lps.cc).
// The mechanical extension of bond i->j with thermal strain:
//   e = |y| - |xi| - (eps_T,i + eps_T,j)/2 |xi| (ModelState::thermal_strain).
// The bond energy of Critical energy (Material::request_bond_energy()), which
// for a plastic or viscous model depends on the path: the work the bond's
// pair force t = t_ij + t_ji has done along its extension so far,
//   w_NP1 = w_N + (t_N + t_NP1) (e_NP1 - e_N) / 2   (trapezoid rule per step),
// stored and dissipated alike, kept per bond (w, t, e; N and NP1: 48 bytes per
// bond, for such blocks only). Summed over the pairs (w beta V_i V_j) it is
// the work of the internal forces: the stored energy plus the dissipation, to
// the trapezoid rule's error. Both owners of a bond compute the same t and e
// (the replicas of the other end's state agree bit for bit), so both halves
// carry the same w.

#include <perideal/material/material.h>

#include <algorithm>
#include <string>
#include <vector>

namespace perideal
{
  class OrdinaryState
  {
  public:
    /// The model's field names start with @p prefix (eps_, ves_): two models
    /// in one scene keep their own constants.
    explicit OrdinaryState(const std::string &prefix)
      : weighted_volume(prefix + "weighted_volume")
      , kappa(prefix + "kappa")
      , alpha(prefix + "alpha")
      , coupling(prefix + "coupling")
      , work(prefix + "work")
      , work_force(prefix + "work_force")
      , work_extension(prefix + "work_extension")
    {}

    const std::string weighted_volume, kappa, alpha, coupling;
    /// The per-bond history of the bond work (above): w, t and e.
    const std::string work, work_force, work_extension;

    /// The bond work's per-bond fields, rewritten whole by every evaluation.
    std::vector<BondField>
    work_fields() const
    {
      return {{work, true}, {work_force, true}, {work_extension, true}};
    }

    /// One evaluation's update of the bond work, from the last accepted step:
    /// the force kernel calls add() with each bond's t and e. Default: none.
    struct WorkUpdate
    {
      WorkUpdate() = default;
      WorkUpdate(const ModelState &state, const OrdinaryState &family)
        : w_N(state.fields.bond_old(family.work))
        , t_N(state.fields.bond_old(family.work_force))
        , e_N(state.fields.bond_old(family.work_extension))
        , w(state.fields.bond(family.work))
        , t(state.fields.bond(family.work_force))
        , e(state.fields.bond(family.work_extension))
      {}

      void
      add(const std::size_t b, const double t_NP1, const double e_NP1) const
      {
        w[b] = w_N[b] + 0.5 * (t_N[b] + t_NP1) * (e_NP1 - e_N[b]);
        t[b] = t_NP1;
        e[b] = e_NP1;
      }

      const double *w_N = nullptr, *t_N = nullptr, *e_N = nullptr;
      double       *w = nullptr, *t = nullptr, *e = nullptr;
    };

    /// a + b, the same bit for bit whichever is which, also where the
    /// compiler fuses a product into the sum (a multiply-add rounds once, so
    /// fma(x, y, b) and fma(u, v, a) differ): the pair force of the bond
    /// work, which both owners must compute alike.
    static double
    symmetric_sum(const double a, const double b)
    {
      return std::min(a, b) + std::max(a, b);
    }

    /// Material::bond_energies() of point @p i: the latest bond work.
    void
    work_energies(const ModelState &state, const unsigned int i, double *energies) const
    {
      const double *latest = state.fields.bond_latest(work);
      std::copy(latest + state.bonds.offsets[i], latest + state.bonds.offsets[i + 1], energies);
    }

    /// The four constant fields above.
    std::vector<PointField>
    constant_fields() const;

    /// Fills them for @p points; refuses blocks of different horizons bonded
    /// to each other (@p path and @p model name the block's subsection and model).
    void
    initialize(const ModelState &state, const std::vector<unsigned int> &points, const double K, const double G,
               const std::string &path, const std::string &model) const;

    /// LPS's Gershgorin bound of the elastic tangent (lps.cc, beta = alpha,
    /// gamma = kappa - alpha/3) with density @p rho.
    double
    stable_time_step(const ModelState &state, const std::vector<unsigned int> &points, const double rho) const;

    /// Calls @p f with the compile-time variants of this state: per-bond
    /// weights (partial volumes), periodic, binary damage, thermal strain.
    template <typename F>
    static void
    variants(const ModelState &state, const F &f)
    {
      with_flag(!state.bonds.volume_fraction.empty(), [&](auto W) {
        with_flag(state.cloud.periodicity.any(), [&](auto P) {
          with_flag(state.broken != nullptr, [&](auto D) {
            with_flag(state.thermal_strain != nullptr, [&](auto T) { f(W, P, D, T); });
          });
        });
      });
    }

    /// variants() plus whether the stage pass applies the fused critical
    /// stretch (ModelState::breaking, set only with binary damage): the
    /// first bond pass then breaks each overstretched bond before it uses it,
    /// and the core runs no damage pass of its own for the block.
    template <typename F>
    static void
    stage_variants(const ModelState &state, const F &f)
    {
      variants(state, [&](auto W, auto P, auto D, auto T) {
        if constexpr (decltype(D)::value)
          with_flag(state.breaking != nullptr, [&](auto B) { f(W, P, D, T, B); });
        else
          f(W, P, D, T, std::false_type());
      });
    }

    /// The fused critical stretch on bond @p b (i->j): the damage pass's
    /// test (break_if_overstretched on the squared lengths) bit for bit;
    /// returns 1 if the bond broke now.
    template <bool periodic>
    static std::uint8_t
    break_bond(const ModelState &state, const BondOrigin &origin, const unsigned int j, const std::size_t b)
    {
      double ev[3], y[3];
      bond_vectors<periodic>(state.cloud.X.data(), state.u, j, origin, state.cloud.periodicity, ev, y);
      return break_if_overstretched(y[0] * y[0] + y[1] * y[1] + y[2] * y[2],
                                    ev[0] * ev[0] + ev[1] * ev[1] + ev[2] * ev[2], state.breaking->squared_limit,
                                    state.breaking->broken[b]);
    }

    /// Bond i->j: |xi| (@p r0), |y| (@p r), the mechanical extension @p e; writes y.
    template <bool periodic, bool thermal>
    static void
    bond(const ModelState &state, const BondOrigin &origin, const unsigned int i, const unsigned int j,
         double (&y)[3], double &r0, double &r, double &e)
    {
      double ev[3];
      bond_vectors<periodic>(state.cloud.X.data(), state.u, j, origin, state.cloud.periodicity, ev, y);
      r0 = std::sqrt(ev[0] * ev[0] + ev[1] * ev[1] + ev[2] * ev[2]);
      r  = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
      e  = r - r0;
      if constexpr (thermal)
        e -= 0.5 * (state.thermal_strain[i] + state.thermal_strain[j]) * r0;
    }

    /// Adds the tangent K = -d(V f)/du of the owned @p points to @p rows for a
    /// force whose bond scalar (both halves) is
    ///   t_b = w_b [|xi| (kappa_i theta_i + kappa_j theta_j) + D_i(b) + D_j(b)],
    /// f_i = sum_b V_j t_b M_b (M = y/|y|), with a deviatoric half D_i(b) of
    /// the trial deviatoric extension eps_b = e_b - theta_i |xi_b|/3 - p_b (p:
    /// a back or plastic extension held fixed within the step) that varies as
    ///   dD_i(b) = a_i d eps_b + eta_i eps_b sum_c w_c eps_c V_c d eps_c.
    /// a_i: @p deviatoric per local point (ghosts current), e.g. alpha_i
    /// (elastic), alpha_i s_i (radial return), alpha_i (1 - lambda_i beta)
    /// (viscoelastic); eta_i: @p eta per local point (nullptr: 0), the
    /// radial return's rank-one term; p: @p back per bond (nullptr: 0);
    /// @p theta the dilatation per local point (ghosted). @p bond_force(i, b,
    /// j, e, r0) returns t_b for the geometric stiffness t (I - M M^T)/|y|.
    /// With de_l = M_l . (du_j(l) - du_i) and dtheta_i = (3/m_i) sum_l w_l
    /// |xi_l| V_l de_l, i's half of bond b varies as
    ///   d(w_b [...]_i) = w_b [a_i de_b + sum_l (|xi_b| g_l + eps_b c_l) de_l],
    ///   g_l = (3/m_i)(kappa_i - a_i/3) w_l |xi_l| V_l,
    ///   c_l = eta_i w_l V_l (eps_l - (S_i/m_i) |xi_l|), S_i = sum_c w_c eps_c V_c |xi_c|,
    /// which enters row i (through f_i) and the rows j of i's neighbors
    /// (through i's half of their bond j->i), as lps.cc's tangent does.
    template <typename BondForce>
    void
    add_tangent(const ModelState &state, const std::vector<unsigned int> &points, TangentRows &rows,
                const double *theta, const double *deviatoric, const double *eta, const double *back,
                const BondForce &bond_force) const
    {
      const double *V     = state.cloud.volume.data();
      const double *m     = state.fields.get(weighted_volume).begin();
      const double *kappa = state.fields.get(this->kappa).begin();
      std::vector<unsigned int> cols;
      std::vector<double>       blocks, M, ga, gc, w_r0, w_eps;
      for (const unsigned int i : points)
        {
          const std::size_t first = state.bonds.offsets[i], n = state.bonds.offsets[i + 1] - first;
          cols.resize(n + 1);
          blocks.assign(9 * (n + 1), 0.0);
          M.assign(3 * n, 0.0);
          ga.assign(3 * n, 0.0);
          gc.assign(3 * n, 0.0);
          w_r0.assign(n, 0.0);
          w_eps.assign(n, 0.0);
          cols[0]          = i;
          const double ai  = deviatoric[i];
          const double ei  = eta ? eta[i] : 0.0;
          const double g_i = m[i] > 0 ? 3 / m[i] * (kappa[i] - ai / 3) : 0.0;
          // First pass: the trial deviatoric extensions and S_i.
          double S = 0;
          for (std::size_t k = 0; k < n; ++k)
            {
              const std::size_t  b = first + k;
              const unsigned int j = state.bonds.neighbor[b];
              cols[k + 1]          = j;
              double xi[3], y[3];
              const auto [r0, r] = bond_geometry(state.cloud, state.u, i, j, xi, y);
              const double w     = bond_weight(state, b);
              const double e     = r - r0 - thermal_extension(state, i, j, r0);
              const double eps   = e - theta[i] * r0 / 3 - (back ? back[b] : 0.0);
              w_r0[k]            = w * r0;
              w_eps[k]           = w * eps;
              S += w * eps * V[j] * r0;
              for (unsigned int d = 0; d < 3; ++d)
                M[3 * k + d] = y[d] / r;
            }
          double cA[3] = {0, 0, 0}, cC[3] = {0, 0, 0}, GA[3] = {0, 0, 0}, GC[3] = {0, 0, 0};
          for (std::size_t k = 0; k < n; ++k)
            {
              const std::size_t  b = first + k;
              const unsigned int j = cols[k + 1];
              double xi[3], y[3];
              const auto [r0, r] = bond_geometry(state.cloud, state.u, i, j, xi, y);
              const double w     = bond_weight(state, b);
              const double e     = r - r0 - thermal_extension(state, i, j, r0);
              const double t     = bond_force(i, b, j, e, r0);
              const double gl    = g_i * w_r0[k] * V[j];
              const double cl    = m[i] > 0 ? ei * V[j] * (w_eps[k] - S / m[i] * w_r0[k]) : 0.0;
              for (unsigned int d = 0; d < 3; ++d)
                {
                  ga[3 * k + d] = gl * M[3 * k + d];
                  gc[3 * k + d] = cl * M[3 * k + d];
                  GA[d] += ga[3 * k + d];
                  GC[d] += gc[3 * k + d];
                  cA[d] += V[j] * w_r0[k] * M[3 * k + d];
                  cC[d] += V[j] * w_eps[k] * M[3 * k + d];
                }
              // Direct: both halves' a d e_b, and the rotation of M.
              const double direct = w * (ai + deviatoric[j]);
              for (unsigned int p = 0; p < 3; ++p)
                for (unsigned int q = 0; q < 3; ++q)
                  {
                    const double MM = M[3 * k + p] * M[3 * k + q];
                    const double A  = V[i] * V[j] * (direct * MM + t * ((p == q) - MM) / r);
                    blocks[9 * (k + 1) + 3 * p + q] = -A;
                    blocks[3 * p + q] += A;
                  }
            }
          // Row i: f_i through i's own coupled terms.
          for (std::size_t l = 0; l < n; ++l)
            for (unsigned int p = 0; p < 3; ++p)
              for (unsigned int q = 0; q < 3; ++q)
                blocks[9 * (l + 1) + 3 * p + q] -= V[i] * (cA[p] * ga[3 * l + q] + cC[p] * gc[3 * l + q]);
          for (unsigned int p = 0; p < 3; ++p)
            for (unsigned int q = 0; q < 3; ++q)
              blocks[3 * p + q] += V[i] * (cA[p] * GA[q] + cC[p] * GC[q]);
          rows.add(i, cols.data(), blocks.data(), n + 1);

          // Rows j: i's half of bond j->i, -V_i (i's half) M_k in f_j.
          if (g_i == 0 && ei == 0)
            continue;
          for (std::size_t k = 0; k < n; ++k)
            {
              if (w_r0[k] == 0)
                continue;
              const unsigned int j = cols[k + 1];
              for (unsigned int p = 0; p < 3; ++p)
                {
                  const double sa = V[j] * V[i] * w_r0[k] * M[3 * k + p];
                  const double sc = V[j] * V[i] * w_eps[k] * M[3 * k + p];
                  for (unsigned int q = 0; q < 3; ++q)
                    {
                      blocks[3 * p + q] = -(sa * GA[q] + sc * GC[q]);
                      for (std::size_t l = 0; l < n; ++l)
                        blocks[9 * (l + 1) + 3 * p + q] = sa * ga[3 * l + q] + sc * gc[3 * l + q];
                    }
                }
              rows.add(j, cols.data(), blocks.data(), n + 1);
            }
        }
    }

    /// Material::released_energy() of a model whose W_i is a closed function
    /// of N per-point sums over the bonds: one pass over @p points' bonds
    /// adds both damage states' sums, nothing is written.
    /// @p add(b, r0, e, w, sums) adds bond b's terms with the weight w =
    /// weight() V_j to sums[0..N) (e: the mechanical extension);
    /// @p energy(i, sums) returns W_i from them.
    template <std::size_t N, typename Add, typename Energy>
    double
    released_energy(const ModelState &before, const ModelState &now, const std::vector<unsigned int> &points,
                    const Add &add, const Energy &energy) const
    {
      double released = 0;
      variants(now, [&](auto W, auto P, auto D, auto T) {
        released = released_sums<N, decltype(W)::value, decltype(P)::value, decltype(D)::value, decltype(T)::value>(
          before, now, points, add, energy);
      });
      return released;
    }

    /// The free thermal extension of bond i-j, 0 without thermal strain (set-up, tangent).
    static double
    thermal_extension(const ModelState &state, const unsigned int i, const unsigned int j, const double r0)
    {
      return state.thermal_strain ? 0.5 * (state.thermal_strain[i] + state.thermal_strain[j]) * r0 : 0.0;
    }

    /// weight() with run-time flags (set-up, tangent).
    static double
    bond_weight(const ModelState &state, const std::size_t b)
    {
      return state.bonds.fraction(b) * (state.broken ? 1.0 - state.broken[b] : 1.0);
    }

    /// The weight of bond @p b: beta_ij with partial volumes, 0 if broken.
    template <bool weighted, bool damaged>
    static double
    weight(const ModelState &state, const std::size_t b)
    {
      double w = weighted ? double(state.bonds.volume_fraction[b]) : 1.0;
      if constexpr (damaged)
        w *= 1.0 - state.broken[b];
      return w;
    }

  private:
    template <std::size_t N, bool weighted, bool periodic, bool damaged, bool thermal, typename Add, typename Energy>
    double
    released_sums(const ModelState &before, const ModelState &now, const std::vector<unsigned int> &points,
                  const Add &add, const Energy &energy) const
    {
      const double       *V        = now.cloud.volume.data();
      const std::size_t  *offsets  = now.bonds.offsets.data();
      const unsigned int *neighbor = now.bonds.neighbor.data();
      const double       *m        = now.fields.get(weighted_volume).begin();
      double              released = 0;
      for (const unsigned int i : points)
        {
          if (m[i] == 0)
            continue;
          const BondOrigin origin(now.cloud.X.data(), now.u, i);
          double           sums[2][N] = {}; // [0]: before, [1]: now
          for (std::size_t b = offsets[i]; b < offsets[i + 1]; ++b)
            {
              const unsigned int j = neighbor[b];
              double             y[3], r0, r, e;
              bond<periodic, thermal>(now, origin, i, j, y, r0, r, e);
              for (unsigned int k = 0; k < 2; ++k)
                add(b, r0, e, weight<weighted, damaged>(k == 0 ? before : now, b) * V[j], sums[k]);
            }
          released += V[i] * (energy(i, sums[0]) - energy(i, sums[1]));
        }
      return released;
    }
  };

  /// A Material of Mitchell's ordinary state-based family: its OrdinaryState
  /// (family) and the bond work of Critical energy, which Elastic plastic and
  /// Viscoelastic keep alike (request_bond_energy() switches it on).
  class OrdinaryStateMaterial : public Material
  {
  public:
    explicit OrdinaryStateMaterial(const std::string &prefix)
      : family(prefix)
    {}

    void
    request_bond_energy() override
    {
      work = true;
    }

    bool
    has_bond_energy() const override
    {
      return work;
    }

    void
    bond_energies(const ModelState &state, const unsigned int i, double *w) const override
    {
      family.work_energies(state, i, w);
    }

  protected:
    /// The model's own per-bond fields @p fields, plus the bond work's if requested.
    std::vector<BondField>
    with_work_fields(std::vector<BondField> fields) const
    {
      if (work)
        for (const BondField &f : family.work_fields())
          fields.push_back(f);
      return fields;
    }

    /// OrdinaryState::variants() and whether the force kernel keeps the bond
    /// work: @p f(W, P, D, T, B).
    template <typename F>
    void
    force_variants(const ModelState &state, const F &f) const
    {
      OrdinaryState::variants(state, [&](auto W, auto P, auto D, auto T) {
        with_flag(work, [&](auto B) { f(W, P, D, T, B); });
      });
    }

    const OrdinaryState family;
    bool                work = false; // keep each bond's work (request_bond_energy())
  };
} // namespace perideal
