// pd_app: run a peridynamic simulation described by a deal.II parameter file.
//   mpirun -np N pd_app params.prm

#include <perideal/base/interrupt.h>
#include <perideal/simulation/simulation.h>

#include <deal.II/base/mpi.h>

#include <chrono>
#include <iostream>
#include <thread>
#include <regex>
#include <sstream>

namespace
{
  const char *usage =
    "Usage: pd_app [options] params.prm\n"
    "  (run in parallel with: mpirun -np N pd_app params.prm)\n"
    "\n"
    "Options:\n"
    "  --help                       this text\n"
    "  --print-parameters           every parameter with its default and documentation\n"
    "  --print-parameters-markdown  the same as the Markdown page doc/parameters.md\n"
    "  --dry-run params.prm         set up, print points, bonds, memory estimate and the\n"
    "                               stable time step, and exit without time stepping\n"
    "  --restart DIR params.prm     continue the run of params.prm from the checkpoint in DIR\n"
    "                               (Output/Checkpoint; same parameters outside Output, same\n"
    "                               number of ranks)\n";

  // Every rank that catches an error comes here. Checks of user input are
  // collective, so normally all ranks arrive and rank 0 alone reports. An
  // error raised on some ranks only would leave the others waiting in a
  // collective call: if not all ranks arrive within a few seconds, each rank
  // that has an error reports it and the whole run is aborted.
  int
  report_error(const std::string &message, const MPI_Comm comm)
  {
    const bool  root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
    MPI_Request request;
    MPI_Ibarrier(comm, &request);
    int        all_arrived = 0;
    const auto start       = std::chrono::steady_clock::now();
    while (!all_arrived &&
           std::chrono::steady_clock::now() - start < std::chrono::seconds(5))
      {
        MPI_Test(&request, &all_arrived, MPI_STATUS_IGNORE);
        if (!all_arrived)
          std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    if (all_arrived)
      {
        if (root)
          perideal::write_to_stderr("Error: " + message + "\n");
        return 1;
      }
    perideal::write_to_stderr("Error: " + message + "\n");
    MPI_Abort(comm, 1);
    return 1;
  }

  std::string
  one_line(const std::string &text)
  {
    return std::regex_replace(std::regex_replace(text, std::regex("\\s+"), " "),
                              std::regex("^ | $"), "");
  }
} // namespace

int
main(int argc, char *argv[])
{
  // SIGTERM, SIGINT: the run stops after the current step (README, "Running").
  // Installed before MPI's start-up, which can take a while, and again after
  // it: under mpirun, Open MPI's start-up puts its own handlers in place.
  perideal::install_interrupt_handlers();
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  perideal::install_interrupt_handlers();
  const MPI_Comm comm = MPI_COMM_WORLD;
  const bool     root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;

  std::vector<std::string> args(argv + 1, argv + argc);
  bool                     dry_run = false;
  std::string              file, restart;
  for (std::size_t i = 0; i < args.size(); ++i)
    {
      const std::string &a = args[i];
      if (a == "--help" || a == "-h")
        {
          if (root)
            std::cout << usage;
          return 0;
        }
      if (a == "--print-parameters" || a == "--print-parameters-markdown")
        {
          if (root)
            perideal::print_parameter_reference(std::cout, a == "--print-parameters-markdown");
          return 0;
        }
      if (a == "--dry-run")
        dry_run = true;
      else if (a == "--restart" || a.rfind("--restart=", 0) == 0)
        {
          restart = a == "--restart" ? (i + 1 < args.size() ? args[++i] : "") : a.substr(10);
          if (restart.empty())
            {
              if (root)
                perideal::write_to_stderr("Error: --restart needs the checkpoint's directory\n" + std::string(usage));
              return 2;
            }
        }
      else if (!a.empty() && a[0] == '-')
        {
          if (root)
            perideal::write_to_stderr("Error: unknown option '" + a + "'\n" + usage);
          return 2;
        }
      else if (file.empty())
        file = a;
      else
        {
          if (root)
            perideal::write_to_stderr("Error: more than one parameter file given ('" + file + "', '" + a + "')\n");
          return 2;
        }
    }
  if (dry_run && !restart.empty())
    {
      if (root)
        perideal::write_to_stderr("Error: --dry-run and --restart exclude each other\n");
      return 2;
    }
  if (file.empty())
    {
      if (root)
        perideal::write_to_stderr("Error: no parameter file given\n" + std::string(usage));
      return 2;
    }

  try
    {
      perideal::Simulation simulation(file, comm);
      if (dry_run)
        simulation.dry_run();
      else
        simulation.run(restart);
    }
  catch (const perideal::Interrupted &e)
    {
      // Every rank stops alike; the shell's code for the signal.
      if (!e.reported)
        report_error(e.what(), comm);
      return 128 + e.signal;
    }
  catch (const dealii::ExceptionBase &e)
    {
      std::ostringstream info;
      e.print_info(info);
      return report_error(one_line(info.str()), comm);
    }
  catch (const std::bad_alloc &)
    {
      // Past the size check before set-up (a lower bound of the need): say
      // what ran out and the way out, not "std::bad_alloc".
      return report_error("out of memory on rank " +
                            std::to_string(dealii::Utilities::MPI::this_mpi_process(comm)) +
                            ": the scene needs more memory than the ranks have (pd_app --dry-run prints "
                            "its size estimate). Use more ranks, on more nodes, or fewer cells (Discretization) "
                            "or a smaller horizon",
                          comm);
    }
  catch (const std::exception &e)
    {
      return report_error(one_line(e.what()), comm);
    }
  return 0;
}
