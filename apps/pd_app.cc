// pd_app: run a peridynamic simulation described by a deal.II parameter file.
//   mpirun -np N pd_app params.prm

#include <perideal/solver/simulation.h>

#include <deal.II/base/mpi.h>

#include <iostream>
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
    "                               stable time step, and exit without time stepping\n";

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
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm comm = MPI_COMM_WORLD;
  const bool     root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;

  std::vector<std::string> args(argv + 1, argv + argc);
  bool                     dry_run = false;
  std::string              file;
  for (const auto &a : args)
    {
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
      else if (!a.empty() && a[0] == '-')
        {
          if (root)
            std::cerr << "Error: unknown option '" << a << "'\n" << usage;
          return 2;
        }
      else if (file.empty())
        file = a;
      else
        {
          if (root)
            std::cerr << "Error: more than one parameter file given ('" << file << "', '" << a << "')\n";
          return 2;
        }
    }
  if (file.empty())
    {
      if (root)
        std::cerr << "Error: no parameter file given\n" << usage;
      return 2;
    }

  try
    {
      perideal::Simulation simulation(file, comm);
      if (dry_run)
        simulation.dry_run();
      else
        simulation.run();
    }
  catch (const dealii::ExceptionBase &e)
    {
      std::ostringstream info;
      e.print_info(info);
      if (root)
        std::cerr << "Error: " << one_line(info.str()) << std::endl;
      return 1;
    }
  catch (const std::exception &e)
    {
      if (root)
        std::cerr << "Error: " << one_line(e.what()) << std::endl;
      return 1;
    }
  return 0;
}
