#include <perideal/base/interrupt.h>

#include <csignal>
#include <cstring>

namespace perideal
{
  namespace
  {
    volatile std::sig_atomic_t received = 0;

    extern "C" void
    record_signal(int signal)
    {
      if (received != 0)
        {
          // A second signal: the user insists. Only async-signal-safe calls.
          std::signal(signal, SIG_DFL);
          std::raise(signal);
          return;
        }
      received = signal;
    }
  } // namespace

  void
  install_interrupt_handlers()
  {
    struct sigaction action;
    std::memset(&action, 0, sizeof(action));
    action.sa_handler = record_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART; // system calls (file writes, MPI's polls) go on
    sigaction(SIGTERM, &action, nullptr);
    sigaction(SIGINT, &action, nullptr);
  }

  int
  local_interrupt_signal()
  {
    return received;
  }

  int
  interrupt_signal(const MPI_Comm comm)
  {
    return dealii::Utilities::MPI::max(static_cast<int>(received), comm);
  }

  std::string
  signal_name(const int signal)
  {
    switch (signal)
      {
        case SIGTERM:
          return "SIGTERM";
        case SIGINT:
          return "SIGINT";
        default:
          return "signal " + std::to_string(signal);
      }
  }
} // namespace perideal
