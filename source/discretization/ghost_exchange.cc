#include <perideal/discretization/ghost_exchange.h>

#include <algorithm>

namespace perideal
{
  GhostExchange::GhostExchange(const std::shared_ptr<const dealii::Utilities::MPI::Partitioner> &partitioner_,
                               const int                                                          tag_)
    : partitioner(partitioner_)
    , tag(tag_)
    , send_buffer(partitioner->n_import_indices())
    , sends(partitioner->import_targets().size(), MPI_REQUEST_NULL)
    , receives(partitioner->ghost_targets().size(), MPI_REQUEST_NULL)
  {}

  GhostExchange::~GhostExchange()
  {
    // Every rank posted the matching receives in the same step.
    MPI_Waitall(receives.size(), receives.data(), MPI_STATUSES_IGNORE);
    MPI_Waitall(sends.size(), sends.data(), MPI_STATUSES_IGNORE);
  }

  void
  GhostExchange::start(double *values)
  {
    const MPI_Comm comm = partitioner->get_mpi_communicator();
    // Ghosts are stored by owner, in the order of ghost_targets().
    double *ghost = values + partitioner->locally_owned_size();
    for (std::size_t k = 0; k < receives.size(); ++k)
      {
        const auto &[rank, count] = partitioner->ghost_targets()[k];
        MPI_Irecv(ghost, count, MPI_DOUBLE, rank, tag, comm, &receives[k]);
        ghost += count;
      }
    MPI_Waitall(sends.size(), sends.data(), MPI_STATUSES_IGNORE);
    double *packed = send_buffer.data();
    for (const auto &[begin, end] : partitioner->import_indices())
      packed = std::copy(values + begin, values + end, packed);
    packed = send_buffer.data();
    for (std::size_t k = 0; k < sends.size(); ++k)
      {
        const auto &[rank, count] = partitioner->import_targets()[k];
        MPI_Isend(packed, count, MPI_DOUBLE, rank, tag, comm, &sends[k]);
        packed += count;
      }
  }

  void
  GhostExchange::finish()
  {
    MPI_Waitall(receives.size(), receives.data(), MPI_STATUSES_IGNORE);
  }
} // namespace perideal
