// The built-in operations of a compute over its region, registered as
// Registry<Reduction> (reduction.h).
#include <perideal/compute/reduction.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class SumReduction : public Reduction
    {
    public:
      double
      reduce(const std::vector<double> &q, const std::vector<double> &, const std::vector<Point<3>> &,
             const MPI_Comm comm) const override
      {
        double sum = 0;
        for (const double value : q)
          sum += value;
        return Utilities::MPI::sum(sum, comm);
      }
    };

    class MeanReduction : public Reduction
    {
    public:
      double
      reduce(const std::vector<double> &q, const std::vector<double> &V, const std::vector<Point<3>> &,
             const MPI_Comm comm) const override
      {
        double sums[2] = {0, 0};
        for (unsigned int j = 0; j < q.size(); ++j)
          {
            sums[0] += V[j] * q[j];
            sums[1] += V[j];
          }
        Utilities::MPI::sum(ArrayView<const double>(sums, 2), comm, ArrayView<double>(sums, 2));
        return sums[1] > 0 ? sums[0] / sums[1] : 0;
      }
    };

    /// Minimum for @p sign 1, Maximum (the minimum of -q) for -1.
    template <int sign>
    class Extremum : public Reduction
    {
    public:
      double
      reduce(const std::vector<double> &q, const std::vector<double> &, const std::vector<Point<3>> &,
             const MPI_Comm comm) const override
      {
        double best = std::numeric_limits<double>::max();
        for (const double value : q)
          best = std::min(best, sign * value);
        return sign * Utilities::MPI::min(best, comm);
      }
    };
    using MinimumReduction = Extremum<1>;
    using MaximumReduction = Extremum<-1>;

    /// Peridigm's Nearest_Point_Data: q at the point (or FE node) of the
    /// region nearest to Location in the reference configuration. Of points
    /// equally near, the one with the smallest (x, y, z) (lexicographic), so
    /// that the choice is the same on any number of ranks.
    class NearestPoint : public Reduction
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Location", "", Patterns::List(Patterns::Double(), 0, 3),
                          "Operation = Nearest point: the place x, y, z (reference configuration) whose nearest "
                          "point of the region gives the value, e.g. the end of a strain gauge.");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path) override
      {
        // The pattern has checked the numbers; empty and short lists pass it.
        const std::string text = prm.get("Location");
        AssertThrow(!text.empty(), ExcMessage(path + "/Location: Operation = Nearest point needs the location "
                                                     "x, y, z whose nearest point gives the value"));
        AssertThrow(Utilities::split_string_list(text, ',').size() == 3,
                    ExcMessage(path + "/Location: expected three numbers x, y, z, got '" + text + "'"));
        location = get_point(prm, "Location");
      }

      bool
      needs_positions() const override
      {
        return true;
      }

      double
      reduce(const std::vector<double> &q, const std::vector<double> &, const std::vector<Point<3>> &x,
             const MPI_Comm comm) const override
      {
        // This rank's best (squared distance, x, y, z, q); then the best of all.
        std::array<double, 5> best{{std::numeric_limits<double>::infinity(), 0, 0, 0, 0}};
        for (unsigned int j = 0; j < q.size(); ++j)
          {
            const std::array<double, 5> c{{x[j].distance_square(location), x[j][0], x[j][1], x[j][2], q[j]}};
            if (std::lexicographical_compare(c.begin(), c.begin() + 4, best.begin(), best.begin() + 4))
              best = c;
          }
        for (const auto &c : Utilities::MPI::all_gather(comm, best))
          if (std::lexicographical_compare(c.begin(), c.begin() + 4, best.begin(), best.begin() + 4))
            best = c;
        return best[4];
      }

    private:
      Point<3> location;
    };
  } // namespace

  PERIDEAL_REGISTER(Reduction, SumReduction, "Sum", "the sum of q.")
  PERIDEAL_REGISTER(Reduction, MeanReduction, "Mean", "volume weighted, sum V q / sum V.")
  PERIDEAL_REGISTER(Reduction, MinimumReduction, "Minimum", "the smallest q.")
  PERIDEAL_REGISTER(Reduction, MaximumReduction, "Maximum", "the largest q.")
  PERIDEAL_REGISTER(Reduction, NearestPoint, "Nearest point",
                    "q at the point (or FE node) of the region nearest to Location in the reference configuration "
                    "(Peridigm's Nearest_Point_Data; of equally near ones, the one with the smallest x, then y, "
                    "then z: the same on any number of ranks).")
} // namespace perideal
