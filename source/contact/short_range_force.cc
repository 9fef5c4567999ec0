// Silling and Askari's short-range force (users' guide 3.9, overview paper
// eq. 4), Peridigm's "Short Range Force": for two points closer than the
// contact radius r_c, a repulsive spring along d = y_j - y_i,
//   f_i = -c (r_c - |d|)/delta V_i V_j d/|d|,   c = 18 k / (pi delta^4),
// k the spring constant (a bulk modulus), delta the horizon; its energy
// c/(2 delta) V_i V_j (r_c - |d|)^2. With a friction coefficient mu
// (Peridigm's friction model), a tangential force on i along the relative
// tangential velocity v_t of j past i (opposing the sliding),
//   |f_t| = min(mu |f_n|, min(m_ij, m_i/n_i, m_j/n_j) |v_t| / dt),
// m_ij = m_i m_j / (m_i + m_j), n_i the number of contacts of i now:
// Coulomb's bound while sliding; below it, a share of the force that stops
// the sliding within the step: at most what stops the pair alone (m_ij), and
// at most each point's mass over its contacts, so that all the contacts of a
// point together stop it and do not throw it back (sticking to within the
// velocity one step of load gives, without a tangential spring and its
// history).
//
// "Time dependent short range force" is the same with k an expression in t.

#include <perideal/base/time_function.h>
#include <perideal/contact/contact_model.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    void
    declare_common(ParameterHandler &prm)
    {
      prm.declare_entry("Contact radius", "0", Patterns::Double(0),
                        "r_c: two points closer than this repel each other (required; about 0.5 to 1 point "
                        "spacing: smaller lets bodies interpenetrate between the points, larger holds them apart "
                        "by more than a spacing).");
      prm.declare_entry("Horizon", "0", Patterns::Double(0),
                        "delta of the force law; 0: the larger of the two points' block horizons.");
      prm.declare_entry("Friction coefficient", "0", Patterns::Double(),
                        "mu >= 0: the tangential force is at most mu times the normal force and opposes the "
                        "sliding (Coulomb); 0: frictionless.");
    }

    /// The pair loop for spring constant @p k (constant over the call).
    template <bool friction>
    void
    short_range_force(const ContactPoints &p, const unsigned int *first, const unsigned int *second,
                      const std::size_t n, const double k, const double r_c, const double given_horizon,
                      const double mu, ContactOutput &out)
    {
      const double c0 = 18 * k / M_PI;
      double       energy = 0, power = 0;
      for (std::size_t q = 0; q < n; ++q)
        {
          const unsigned int i = first[q], j = second[q];
          const double *ui = p.uv + p.stride * i, *uj = p.uv + p.stride * j; // u, then v with friction
          const double  d[3] = {(p.X[3 * j] + uj[0]) - (p.X[3 * i] + ui[0]),
                                (p.X[3 * j + 1] + uj[1]) - (p.X[3 * i + 1] + ui[1]),
                                (p.X[3 * j + 2] + uj[2]) - (p.X[3 * i + 2] + ui[2])};
          const double  r2   = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
          if (!(r2 < r_c * r_c) || r2 == 0)
            continue;
          const double r     = std::sqrt(r2);
          const double delta = given_horizon > 0 ? given_horizon : std::max(p.horizon[i], p.horizon[j]);
          const double d2    = delta * delta;
          const double c     = c0 / (d2 * d2 * delta) * (p.volume[i] * p.volume[j]); // c_S / delta V_i V_j
          const double gap   = r_c - r;
          const double fn    = c * gap; // |f_n|
          const double s     = fn / r;
          double       f[3]  = {-s * d[0], -s * d[1], -s * d[2]};
          energy += 0.25 * c * gap * gap; // half of c gap^2 / 2
          if constexpr (friction)
            {
              const double vr[3] = {uj[3] - ui[3], uj[4] - ui[4], uj[5] - ui[5]};
              const double vn    = (vr[0] * d[0] + vr[1] * d[1] + vr[2] * d[2]) / r2;
              const double vt[3] = {vr[0] - vn * d[0], vr[1] - vn * d[1], vr[2] - vn * d[2]};
              const double speed = std::sqrt(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
              const double mi = p.mass[i], mj = p.mass[j];
              if (speed > 0 && mi > 0 && mj > 0)
                {
                  const double share = std::min({(mi * mj) / (mi + mj), mi / p.contacts[i], mj / p.contacts[j]});
                  const double stop  = p.dt > 0 ? share * speed / p.dt : mu * fn;
                  const double ft   = std::min(mu * fn, stop) / speed;
                  for (unsigned int c = 0; c < 3; ++c)
                    f[c] += ft * vt[c];
                  // f_t . (v_i - v_j) = -ft |v_t|^2, half of it here.
                  power -= 0.5 * ft * speed * speed;
                }
            }
          const double inverse_volume = 1.0 / p.volume[i];
          for (unsigned int c = 0; c < 3; ++c)
            out.force[3 * i + c] += f[c] * inverse_volume;
        }
      out.energy += energy;
      out.friction_power += power;
    }
  } // namespace

  namespace
  {
    class ShortRangeForce : public ContactModel
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Spring constant", "0", Patterns::Double(0),
                          "k of c = 18 k / (pi delta^4) (a bulk modulus; Peridigm's Spring Constant): the "
                          "stiffness of contact relative to the material's bonds.");
        declare_common(prm);
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path) override
      {
        k = prm.get_double("Spring constant");
        AssertThrow(k > 0, ExcMessage(path + "/Spring constant must be positive (it is " + prm.get("Spring constant") + ")"));
        parse_common(prm, path);
      }

      double
      contact_radius() const override
      {
        return r_c;
      }

      bool
      uses_contact_counts() const override
      {
        return mu > 0;
      }

      bool
      uses_velocity() const override
      {
        return mu > 0;
      }

      double
      stiffness(const double horizon, const double) const override
      {
        const double delta = horizon_for(horizon);
        return 18 * k / (M_PI * std::pow(delta, 5));
      }

      void
      compute_force(const ContactPoints &points, const unsigned int *first, const unsigned int *second,
                    const std::size_t n, ContactOutput &out) const override
      {
        evaluate(points, first, second, n, k, out);
      }

    protected:
      void
      parse_common(ParameterHandler &prm, const std::string &path)
      {
        r_c     = prm.get_double("Contact radius");
        horizon = prm.get_double("Horizon");
        mu      = prm.get_double("Friction coefficient");
        AssertThrow(r_c > 0, ExcMessage(path + "/Contact radius must be positive (it is " + prm.get("Contact radius") +
                                        "): two points closer than it repel each other"));
        AssertThrow(mu >= 0, ExcMessage(path + "/Friction coefficient must be 0 or positive (it is " +
                                        prm.get("Friction coefficient") + ")"));
      }

      double
      horizon_for(const double block_horizon) const
      {
        return horizon > 0 ? horizon : block_horizon;
      }

      void
      evaluate(const ContactPoints &points, const unsigned int *first, const unsigned int *second, const std::size_t n,
               const double spring, ContactOutput &out) const
      {
        if (mu > 0)
          short_range_force<true>(points, first, second, n, spring, r_c, horizon, mu, out);
        else
          short_range_force<false>(points, first, second, n, spring, r_c, horizon, mu, out);
      }

      double k = 0, r_c = 0, horizon = 0, mu = 0;
    };

    class TimeDependentShortRangeForce : public ShortRangeForce
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Spring constant", "0", Patterns::Anything(),
                          "k(t) as a muparser expression in the time t alone (e.g. '1e9*min(1, t/1e-5)'; x, y "
                          "and z are refused): a contact that stiffens or softens in time (Peridigm's Time "
                          "Dependent Short Range Force).");
        declare_common(prm);
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path) override
      {
        function = std::make_shared<TimeFunction>(prm.get("Spring constant"), path + "/Spring constant");
        parse_common(prm, path);
      }

      double
      stiffness(const double horizon, const double time) const override
      {
        return 18 * spring(time) / (M_PI * std::pow(horizon_for(horizon), 5));
      }

      void
      compute_force(const ContactPoints &points, const unsigned int *first, const unsigned int *second,
                    const std::size_t n, ContactOutput &out) const override
      {
        evaluate(points, first, second, n, spring(points.time), out);
      }

    private:
      double
      spring(const double t) const
      {
        const double value = (*function)(t);
        AssertThrow(std::isfinite(value) && value >= 0,
                    ExcMessage(function->text() + " (Contact models: Spring constant) gives " + std::to_string(value) +
                               " at t = " + std::to_string(t) + ": it must be finite and not negative"));
        return value;
      }

      std::shared_ptr<TimeFunction> function;
    };
  } // namespace

  PERIDEAL_REGISTER(ContactModel, ShortRangeForce, "Short range force",
                    "Silling and Askari's repulsive spring between points closer than the contact radius, "
                    "c = 18 k/(pi delta^4) (Peridigm's Short Range Force), with Coulomb friction.")
  PERIDEAL_REGISTER(ContactModel, TimeDependentShortRangeForce, "Time dependent short range force",
                    "the short range force with the spring constant an expression in t.")
} // namespace perideal
