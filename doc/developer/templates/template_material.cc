// A template material: copy this file to source/material/my_material.cc,
// rename the class and the registered name, add the file to PERIDEAL_SOURCES
// in CMakeLists.txt (doc/developer/adding_a_model.md walks through it).
//
// The physics: a bond-based micro-elastic material with a conical
// micromodulus, c(|xi|) = c0 (1 - |xi|/delta). Bond i-j pulls point i with
//   f = c(|xi|) s (1 - d) V_j M,   s = (|y| - |xi|)/|xi|,  M = y/|y|,
// y = y_j - y_i the deformed bond, d its damage (0 or 1). The bond's energy
// w = c s^2 |xi| / 2 goes half to each end: W_i = 1/4 sum_j c s^2 |xi| V_j.
// c0 follows from matching the energy of an isotropic expansion s = eps to the
// continuum's 9/2 K eps^2: 1/4 c0 eps^2 int_0^delta (1 - r/delta) r 4 pi r^2 dr
// = c0 eps^2 pi delta^4 / 20, so c0 = 90 K / (pi delta^4). Bond based, so
// Poisson's ratio is 1/4 and G = 3K/5: one of K, E, G gives the moduli
// (parse_bond_based_elastic_constants, elastic_constants.h).
// Thermal strain (every model has it): the core passes the free thermal
// strain eps_T = alpha (T - T_ref) of every point, alpha that of the point's
// own material (ModelState::thermal_strain, nullptr without a temperature
// field; this model returns its alpha from thermal_expansion_coefficient()).
// s is the mechanical stretch s = (|y| - |xi|)/|xi| - (eps_T,i + eps_T,j)/2,
// the same for both ends, in the force, the energy, the tangent and the peak
// stretch.
//
// The state it keeps, to show point_fields() and bond_fields():
// - template_bond_peak (per bond, history): the largest stretch the bond has
//   had in accepted steps, N and NP1;
// - template_peak_stretch (per point, history, output "Peak stretch"): the
//   largest of its bonds' peaks.
// Neither changes the force; a plasticity or fatigue law would keep its state
// the same way.
// Left out to stay short: blocks of different horizons (bonds in one family
// only, Bonds::family; see pmb.cc) and coupling to finite elements
// (weight_energy()).
//
// The file is compiled into the test suite (tests/models/CMakeLists.txt), so
// it cannot rot: the conformance suite checks it as "Template material", and
// models.templates runs it with the template damage model.

#include <perideal/material/elastic_constants.h>
#include <perideal/material/material.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class TemplateMaterial : public Material
    {
    public:
      // Keys, declared inside Materials/NAME beside "Model". Each needs a
      // default the model accepts: the conformance suite sets only the elastic
      // constants (Density, Bulk modulus, ...) and leaves the rest.
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Density", "0", Patterns::Double(), "Mass density rho.");
        declare_elastic_constants(prm);
        declare_thermal_expansion(prm);
      }

      // Read the keys; refuse bad values naming the key (path is
      // "Materials/NAME"), so that a user sees which line to fix.
      void
      parse_parameters(ParameterHandler &prm, const std::string &path) override
      {
        rho = prm.get_double("Density");
        require_positive(rho, path + "/Density");
        K                 = parse_bond_based_elastic_constants(prm, path).K;
        thermal_expansion = parse_thermal_expansion(prm, path);
      }

      // The moduli: the report, the stable time step checks and the
      // conformance suite's homogeneous-deformation check use them.
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

      // The state the core allocates for this model (field_store.h). History
      // fields have two copies: read N with old()/bond_old(), write NP1 with
      // get()/bond(); the core commits (N = NP1) once per accepted step.
      std::vector<PointField>
      point_fields() const override
      {
        return {{"template_peak_stretch", FieldUse::history, 1, "Peak stretch"}};
      }
      std::vector<BondField>
      bond_fields() const override
      {
        return {{"template_bond_peak"}};
      }

      // No constant fields and no stage (a bond-based force needs nothing of
      // the neighbors but their displacement), so initialize() and
      // compute_stage() keep the defaults.

      // Force density of every point in @p points, added to state.force; its
      // energy density if state.energy is set. NP1 of the history from N and
      // the current state only: Newton may evaluate many trial states per step.
      void
      compute_force(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        // Compile-time variants keep the bond loop free of a branch per bond.
        with_flag(state.cloud.periodicity.any(), [&](auto periodic) {
          with_flag(state.energy != nullptr, [&](auto energy) {
            with_flag(state.thermal_strain != nullptr, [&](auto heated) {
              kernel<decltype(periodic)::value, decltype(energy)::value, decltype(heated)::value>(state, points);
            });
          });
        });
      }

      // A lower bound of the Verlet limit: the Gershgorin bound of the tangent
      // at the reference state, dt_i = sqrt(2 rho / sum_j c V_j / |xi|).
      double
      stable_time_step(const ModelState &state, const std::vector<unsigned int> &points) const override
      {
        double dt = std::numeric_limits<double>::max();
        for (const unsigned int i : points)
          {
            double sum = 0;
            for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
              {
                const unsigned int j  = state.bonds.neighbor[b];
                const double       r0 = state.cloud.bond_vector(i, j).norm();
                sum += micromodulus(r0) * state.cloud.volume[j] * state.bonds.fraction(b) / r0;
              }
            if (sum > 0)
              dt = std::min(dt, std::sqrt(2 * rho / sum));
          }
        return dt;
      }

      // A point's force depends on its own family only.
      unsigned int
      coupling_hops() const override
      {
        return 1;
      }

      // The analytic tangent -d(V_i f_i)/du in 3x3 blocks (without it the
      // implicit solvers take finite differences). A pair force's bond block is
      // add_pair_bond_tangent() (material.h): A_ij = c V_j d(s M)/dy, K_ij =
      // -V_i A_ij, K_ii = V_i sum_j A_ij. A state-based material writes its own
      // (lps.cc).
      bool
      add_tangent(const ModelState &state, const std::vector<unsigned int> &points, TangentRows &rows) const override
      {
        std::vector<unsigned int> cols;
        std::vector<double>       blocks;
        for (const unsigned int i : points)
          {
            const std::size_t first = state.bonds.offsets[i], n = state.bonds.offsets[i + 1] - first;
            cols.assign(1, i);
            blocks.assign(9 * (n + 1), 0.0);
            for (std::size_t k = 0; k < n; ++k)
              {
                const std::size_t  b = first + k;
                const unsigned int j = state.bonds.neighbor[b];
                cols.push_back(j);
                if (state.broken && state.broken[b])
                  continue;
                double xi[3], y[3];
                const auto [r0, r] = bond_geometry(state.cloud, state.u, i, j, xi, y);
                const double cv = micromodulus(r0) * state.cloud.volume[j] * state.bonds.fraction(b) *
                                  state.cloud.volume[i];
                add_pair_bond_tangent(blocks.data(), k, cv, y, r0, r, thermal_stretch(state, i, j));
              }
            rows.add(i, cols.data(), blocks.data(), n + 1);
          }
        return true;
      }

      // Left out, each with a working default: weight_energy() (coupling to a
      // continuum block; without it the material cannot border one) and
      // fuses_stretch_criterion() (a critical stretch tested inside the bond
      // loop, a speed-up only).

    private:
      double rho = 0, K = 0, thermal_expansion = 0;

      /// The free thermal stretch of bond i-j, 0 without thermal strain.
      double
      thermal_stretch(const ModelState &state, const unsigned int i, const unsigned int j) const
      {
        if (!state.thermal_strain)
          return 0;
        return 0.5 * (state.thermal_strain[i] + state.thermal_strain[j]);
      }

      /// c(|xi|) = c0 (1 - |xi|/delta), c0 = 90 K / (pi delta^4).
      double
      micromodulus(const double r0) const
      {
        return 90 * K / (M_PI * std::pow(horizon, 4)) * (1 - r0 / horizon);
      }

      // The hot loop: flat arrays, no allocation, virtual call or MPI. Both
      // owners of a bond take its vectors from bond_vectors(), so they see the
      // same lengths to the last bit.
      template <bool periodic, bool energy, bool heated>
      void
      kernel(const ModelState &state, const std::vector<unsigned int> &points) const
      {
        const double      *X        = state.cloud.X.data();
        const double      *V        = state.cloud.volume.data();
        FieldStore        &fields   = state.fields;
        const double      *peak_n   = fields.bond_old("template_bond_peak");
        double            *peak_np1 = fields.bond("template_bond_peak");
        const VectorType  &point_n  = fields.old("template_peak_stretch");
        VectorType        &point_np1 = fields.get("template_peak_stretch");
        for (const unsigned int i : points)
          {
            const BondOrigin origin(X, state.u, i);
            double           f[3] = {0, 0, 0}, w = 0, peak = point_n.local_element(i);
            for (std::size_t b = state.bonds.offsets[i]; b < state.bonds.offsets[i + 1]; ++b)
              {
                const unsigned int j = state.bonds.neighbor[b];
                double             e[3], y[3];
                bond_vectors<periodic>(X, state.u, j, origin, state.cloud.periodicity, e, y);
                const double r0 = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
                const double r  = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
                const double s  = (r - r0) / r0 - (heated ? thermal_stretch(state, i, j) : 0.0);
                // The history of every bond, broken ones too: the largest
                // stretch it has had, whatever broke it.
                peak_np1[b] = std::max(peak_n[b], s);
                peak        = std::max(peak, peak_np1[b]);
                if (state.broken && state.broken[b])
                  continue;
                const double c  = micromodulus(r0);
                const double Vj = V[j] * state.bonds.fraction(b); // partial volumes, if any
                const double k  = c * s * Vj / r;
                for (unsigned int d = 0; d < 3; ++d)
                  f[d] += k * y[d];
                if (energy)
                  w += 0.25 * c * s * s * r0 * Vj;
              }
            for (unsigned int d = 0; d < 3; ++d)
              state.force[3 * i + d] += f[d];
            if (energy)
              state.energy[i] += w;
            point_np1.local_element(i) = peak;
          }
      }
    };

    // Registration: the name users give as Materials/NAME/Model and a line of
    // documentation for the parameter reference. Here it registers into the
    // test programs that compile this file, not into pd_app.
  } // namespace
  PERIDEAL_REGISTER(Material, TemplateMaterial, "Template material",
                    "Template (doc/developer/templates): bond based, conical micromodulus "
                    "c0 (1 - |xi|/delta), with a peak-stretch history. Keys: Density, one of Bulk modulus, "
                    "Young's modulus, Shear modulus, Thermal expansion coefficient.")
} // namespace perideal
