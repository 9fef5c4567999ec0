// The built-in operations of a compute over its region, registered as
// Registry<Reduction> (reduction.h).
#include <perideal/compute/reduction.h>

#include <algorithm>
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
      reduce(const std::vector<double> &q, const std::vector<double> &, const MPI_Comm comm) const override
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
      reduce(const std::vector<double> &q, const std::vector<double> &V, const MPI_Comm comm) const override
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
      reduce(const std::vector<double> &q, const std::vector<double> &, const MPI_Comm comm) const override
      {
        double best = std::numeric_limits<double>::max();
        for (const double value : q)
          best = std::min(best, sign * value);
        return sign * Utilities::MPI::min(best, comm);
      }
    };
    using MinimumReduction = Extremum<1>;
    using MaximumReduction = Extremum<-1>;
  } // namespace

  PERIDEAL_REGISTER(Reduction, SumReduction, "Sum", "the sum of q.")
  PERIDEAL_REGISTER(Reduction, MeanReduction, "Mean", "volume weighted, sum V q / sum V.")
  PERIDEAL_REGISTER(Reduction, MinimumReduction, "Minimum", "the smallest q.")
  PERIDEAL_REGISTER(Reduction, MaximumReduction, "Maximum", "the largest q.")
} // namespace perideal
