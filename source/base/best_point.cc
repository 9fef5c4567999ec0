#include <perideal/base/best_point.h>

#include <cmath>
#include <cstring>
#include <iomanip>
#include <sstream>
#include <vector>

namespace perideal
{
  bool
  BestPoint::beats(const BestPoint &other) const
  {
    if (!found || std::isnan(value))
      return false;
    if (!other.found)
      return true;
    if (value != other.value)
      return order == Order::largest ? value > other.value : value < other.value;
    if (kind != other.kind)
      return kind < other.kind;
    return id < other.id;
  }

  void
  BestPoint::consider(const double value_, const std::uint64_t id_, const double *x_, const Kind kind_,
                      const double tag_)
  {
    BestPoint candidate(order);
    candidate.found = true;
    candidate.value = value_;
    candidate.id    = id_;
    candidate.kind  = kind_;
    candidate.x     = {{x_[0], x_[1], x_[2]}};
    candidate.tag   = tag_;
    if (candidate.beats(*this))
      *this = candidate;
  }

  namespace
  {
    // What one rank offers, as plain bytes.
    struct Offer
    {
      double        value, x[3], tag;
      std::uint64_t id;
      std::int32_t  found, kind;
    };
  } // namespace

  BestPoint
  BestPoint::global(const MPI_Comm comm) const
  {
    Offer mine;
    std::memset(&mine, 0, sizeof(mine));
    mine.value = value;
    for (unsigned int d = 0; d < 3; ++d)
      mine.x[d] = x[d];
    mine.tag   = tag;
    mine.id    = id;
    mine.found = found && !std::isnan(value);
    mine.kind  = static_cast<std::int32_t>(kind);
    const unsigned int n_ranks = dealii::Utilities::MPI::n_mpi_processes(comm);
    std::vector<Offer> all(n_ranks);
    const int ierr = MPI_Allgather(&mine, sizeof(Offer), MPI_BYTE, all.data(), sizeof(Offer), MPI_BYTE, comm);
    AssertThrowMPI(ierr);
    // Every rank picks from the same offers in the same order: the same winner.
    BestPoint best(order);
    for (const Offer &o : all)
      {
        BestPoint candidate(order);
        candidate.found = o.found != 0;
        candidate.value = o.value;
        candidate.id    = o.id;
        candidate.kind  = static_cast<Kind>(o.kind);
        candidate.x     = {{o.x[0], o.x[1], o.x[2]}};
        candidate.tag   = o.tag;
        if (candidate.beats(best))
          best = candidate;
      }
    return best;
  }

  std::string
  BestPoint::describe() const
  {
    std::ostringstream o;
    o << std::setprecision(4);
    o << (kind == Kind::point ? "point " : "FE degree of freedom ") << id << " at (" << x[0] << ", " << x[1] << ", "
      << x[2] << ")";
    return o.str();
  }
} // namespace perideal
