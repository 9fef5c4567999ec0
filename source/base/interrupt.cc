#include <perideal/base/interrupt.h>

#include <sys/stat.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <iostream>
#include <unistd.h>

namespace perideal
{
  namespace
  {
    volatile std::sig_atomic_t received = 0;

    // Whether standard output can hold a writer up (a terminal, a pipe, a
    // socket; a file or /dev/null cannot). Decided when the handlers are
    // installed: the handler itself makes async-signal-safe calls only.
    volatile std::sig_atomic_t stdout_may_block = 0;

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
      // The rest of the run's console output (the step, the summary) goes to
      // standard error. Open MPI's mpirun, stopping a job, sleeps before it
      // signals the ranks and again before it kills them, and reads none of
      // their output meanwhile: rank 0, writing its progress, fills its
      // terminal (about 20 KB) and blocks in write() until the kill, never
      // reaching the end of the step. The blocked write is restarted
      // (SA_RESTART) on the new descriptor and goes through; standard error is
      // a pipe that holds 64 KiB and carries little else.
      if (stdout_may_block != 0)
        dup2(STDERR_FILENO, STDOUT_FILENO);
    }
  } // namespace

  void
  install_interrupt_handlers()
  {
    struct stat out;
    stdout_may_block = fstat(STDOUT_FILENO, &out) == 0 &&
                       (S_ISFIFO(out.st_mode) || S_ISSOCK(out.st_mode) || isatty(STDOUT_FILENO) != 0);
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
  void
  write_to_stderr(const std::string &text)
  {
    std::cerr.flush(); // what went before comes first
    for (std::size_t at = 0; at < text.size();)
      {
        const ssize_t written = ::write(2, text.data() + at, text.size() - at);
        if (written < 0 && errno == EINTR)
          continue;
        if (written <= 0)
          return;
        at += static_cast<std::size_t>(written);
      }
  }
} // namespace perideal
