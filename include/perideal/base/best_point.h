#pragma once
// The one point a located message names ("point 17 at (x, y, z)"), the same
// on every rank and a real point: each rank offers its best candidate (a
// value, a global id, the position), the global best wins (ties: the smaller
// kind, then the smaller id, so 1 and 2 ranks name the same point) and every
// rank gets the winner's id and position. A rank without a candidate does not
// take part (no sentinel value, no averaged position).

#include <deal.II/base/mpi.h>

#include <array>
#include <cstdint>
#include <string>

namespace perideal
{
  class BestPoint
  {
  public:
    enum class Order
    {
      largest,
      smallest
    };
    /// What the id counts: PD points (cloud.gid) or FE degrees of freedom.
    enum class Kind
    {
      point,
      fe_dof
    };

    explicit BestPoint(const Order order = Order::largest)
      : order(order)
    {}

    /// Keeps the candidate if it beats the one kept (a NaN value never does).
    void
    consider(const double value, const std::uint64_t id, const double *x, const Kind kind = Kind::point,
             const double tag = 0);

    /// The best candidate over all ranks of @p comm, the same on every rank
    /// (found is false if no rank has one). Collective.
    BestPoint
    global(const MPI_Comm comm) const;

    /// "point ID at (x, y, z)" or "FE degree of freedom ID at (x, y, z)".
    std::string
    describe() const;

    Order                 order;
    bool                  found = false;
    double                value = 0;
    std::uint64_t         id    = 0;
    Kind                  kind  = Kind::point;
    std::array<double, 3> x{{0, 0, 0}};
    double                tag = 0; // a caller's datum that travels with the winner (a block index)

  private:
    bool
    beats(const BestPoint &other) const;
  };
} // namespace perideal
