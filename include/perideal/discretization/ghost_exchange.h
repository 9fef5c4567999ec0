#pragma once
// The per-step ghost update of one per-point field, split so that bond loops
// can run while it is in flight.
//
// deal.II's update_ghost_values_finish() waits for this rank's sends as well
// as its receives. A send completes only when the receiving rank takes part in
// MPI, so every finish made the ranks meet, and a rank that ran ahead waited
// for the other at every small jitter. Here finish() waits for the receives
// only: a rank waits only when another has not yet started the exchange. The
// sends are completed at the next start(), before their buffer is refilled,
// when they have long arrived.

#include <deal.II/base/mpi.h>
#include <deal.II/base/partitioner.h>

#include <memory>
#include <vector>

namespace perideal
{
  class GhostExchange
  {
  public:
    /// For vectors on @p partitioner; @p tag keeps exchanges that are in
    /// flight at the same time apart.
    GhostExchange(const std::shared_ptr<const dealii::Utilities::MPI::Partitioner> &partitioner,
                  const int                                                          tag);
    ~GhostExchange();
    GhostExchange(const GhostExchange &) = delete;
    GhostExchange &
    operator=(const GhostExchange &) = delete;

    /// Sends the owned values others hold as ghosts and posts the receives
    /// into the ghost part of @p values (owned entries first, then ghosts).
    /// The ghost part must not be read until finish().
    void
    start(double *values);

    /// Waits until the ghost values have arrived.
    void
    finish();

  private:
    std::shared_ptr<const dealii::Utilities::MPI::Partitioner> partitioner;
    int                                                        tag;
    std::vector<double>                                        send_buffer;
    std::vector<MPI_Request>                                   sends, receives;
  };
} // namespace perideal
