// Time dependent critical stretch (Peridigm's "User Defined Time Dependent
// Critical Stretch"): bond i-j breaks for good when its stretch
// s = (|y_j - y_i| - |xi|)/|xi| exceeds s_c(t), an expression in the time t
// evaluated at the time of each evaluation that may break bonds, e.g. a
// material that weakens as it ages, or a limit lowered to drive a crack at a
// chosen rate. A bond that survived the limits so far breaks the first time
// its stretch exceeds the current one, so a falling s_c breaks bonds at rest.
// It is a stretch criterion like Critical stretch: the core applies it with
// the same rule across blocks (the smaller s_c(t) of the two blocks' limits,
// BondStretchLimits, refreshed at every new time), and PMB and LPS fuse it
// into their force loop, so the cost per bond is that of Critical stretch.
// Like it, it compares the total stretch (a thermal strain is not
// subtracted; doc/thermal.md).

#include <perideal/base/time_function.h>
#include <perideal/damage/damage_model.h>

#include <cmath>
#include <memory>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class TimeDependentCriticalStretch : public StretchCriterion
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Critical stretch", "", Patterns::Anything(),
                          "s_c(t) > 0: an expression in the time t (muparser, as the boundary conditions), "
                          "e.g. 0.002 * (1 - t / 1e-3) + 1e-4. Evaluated at the time of each evaluation "
                          "that may break bonds; a value that is not finite or not positive stops the run.");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path) override
      {
        where      = path + "/Critical stretch";
        expression = std::make_unique<TimeFunction>(prm.get("Critical stretch"), where);
      }

      void
      initialize(const Material &, const double) override
      {}

      double
      critical_stretch(const double t) const override
      {
        // The same t on every rank, so every rank stops alike.
        const double sc = (*expression)(t);
        AssertThrow(std::isfinite(sc) && sc > 0,
                    ExcMessage(where + ": '" + expression->text() + "' gives s_c = " + to_text(sc) + " at t = " +
                               to_text(t) + "; the critical stretch must be positive and finite at every time "
                               "of the run"));
        return sc;
      }

      bool
      time_dependent() const override
      {
        return true;
      }

      std::string
      describe() const override
      {
        std::ostringstream out;
        out << "time dependent critical stretch s_c(t) = " << expression->text();
        return out.str();
      }

    private:
      std::string                 where;
      std::unique_ptr<TimeFunction> expression;

      static std::string
      to_text(const double x)
      {
        std::ostringstream out;
        out << x;
        return out.str();
      }
    };
  } // namespace

  PERIDEAL_REGISTER(DamageModel, TimeDependentCriticalStretch, "Time dependent critical stretch",
                    "Bond breaks when its stretch exceeds s_c(t), an expression in the time t (Peridigm's User "
                    "Defined Time Dependent Critical Stretch). Across blocks, as Critical stretch: the smaller "
                    "s_c of the two blocks at the current time.")
} // namespace perideal
