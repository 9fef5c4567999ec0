// Interface aware (Peridigm's Interface Aware damage model, with the interface
// given a strength of its own): a critical stretch for the bonds within the
// block, s_c, and one for the bonds from the block to any other block, s_i
// (0: s_c, which is Peridigm's rule, the smaller of the two points' s_c). A
// bond between blocks A and B breaks for good when its stretch exceeds the
// smaller of the values A and B set on their interfaces (a block with
// Critical stretch sets its s_c there), so a bimaterial joint weaker than
// either material is one key: s_i below both blocks' s_c. It is a stretch
// criterion: the core applies it through BondStretchLimits, one limit per
// pair of blocks, which both owners of a bond look up alike, and PMB and LPS
// fuse it into their first bond pass where a block's bonds all meet one limit
// (otherwise the separate pass looks the limit up per bond).

#include <perideal/damage/damage_model.h>

#include <iomanip>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class InterfaceAware : public StretchCriterion
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Critical stretch", "0", Patterns::Double(),
                          "s_c > 0 of the bonds within the block.");
        prm.declare_entry("Interface critical stretch", "0", Patterns::Double(),
                          "s_i of the bonds from the block to other blocks; a bond between two blocks breaks at "
                          "the smaller of the two blocks' interface values (a Critical stretch block's is its "
                          "s_c). 0: s_c, Peridigm's rule.");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path) override
      {
        sc = prm.get_double("Critical stretch");
        si = prm.get_double("Interface critical stretch");
        AssertThrow(sc > 0, ExcMessage(path + "/Critical stretch must be positive, got " + prm.get("Critical stretch")));
        AssertThrow(si >= 0, ExcMessage(path + "/Interface critical stretch must be >= 0 (0: the Critical stretch), got " +
                                        prm.get("Interface critical stretch")));
        if (si == 0)
          si = sc;
      }

      void
      initialize(const Material &, const double) override
      {}

      double
      critical_stretch(const double) const override
      {
        return sc;
      }

      double
      interface_critical_stretch(const double) const override
      {
        return si;
      }

      std::string
      describe() const override
      {
        std::ostringstream out;
        out << "interface aware: s_c = " << std::setprecision(6) << sc << " within, " << si << " to other blocks";
        return out.str();
      }

    private:
      double sc = 0, si = 0;
    };
  } // namespace

  PERIDEAL_REGISTER(DamageModel, InterfaceAware, "Interface aware",
                    "Critical stretch s_c within the block and s_i to other blocks (Peridigm's Interface Aware, "
                    "with the interface's own strength): a bond between blocks breaks at the smaller of the two "
                    "blocks' interface values.")
} // namespace perideal
