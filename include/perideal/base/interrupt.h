#pragma once
// Interrupted runs: SIGTERM and SIGINT (a batch system's stop, mpirun's
// forwarding, a user's Ctrl-C) only set a flag here; the integrators look at
// it collectively once per step, finish the step, write its output and stop
// with an Interrupted exception (pd_app: one "Error: interrupted by ..." line,
// exit code 128 + the signal). From the signal on, the console output goes to
// standard error where standard output could block (a terminal, a pipe). A
// second signal while the first is being handled ends the process at once
// (the default action).

#include <deal.II/base/mpi.h>

#include <stdexcept>
#include <string>

namespace perideal
{
  /// Installs the handlers for SIGTERM and SIGINT (once, on every rank).
  void
  install_interrupt_handlers();

  /// The signal this rank has received, 0 if none. Not collective.
  int
  local_interrupt_signal();

  /// The signal any rank of @p comm has received (the largest number if
  /// several), 0 if none; the same on every rank. Collective.
  int
  interrupt_signal(const MPI_Comm comm);

  /// Writes @p text to standard error with one write() (repeated only for
  /// what a signal or a full pipe cut short): under mpirun another rank's
  /// line cannot land between an "Error: " and its message.
  void
  write_to_stderr(const std::string &text);

  /// "SIGTERM", "SIGINT", else "signal N".
  std::string
  signal_name(const int signal);

  /// Thrown on every rank alike when a run stops for a signal.
  class Interrupted : public std::runtime_error
  {
  public:
    Interrupted(const int signal, const std::string &message, const bool reported = false)
      : std::runtime_error(message)
      , signal(signal)
      , reported(reported)
    {}
    int  signal;
    bool reported; // the "Error: ..." line is printed already (before the summary)
  };
} // namespace perideal
