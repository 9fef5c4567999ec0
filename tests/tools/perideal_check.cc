// perideal_check MODE ARGUMENTS...: the checks of a pd_app run's globals CSV
// and output, run by the test runner (tests/tools/run.sh check) after pd_app.
// The modes and their arguments are described in check_globals.cc (globals),
// check_quasistatic.cc (quasistatic), check_stability.cc (stability) and
// check_damage.cc (softening).
// Exit code: 0 every check passed, 1 a check failed, 2 bad arguments or input.

#include "check.h"

#include <iostream>
#include <string>

int
main(int argc, char *argv[])
{
  const std::string mode = argc > 1 ? argv[1] : "";
  // Each mode sees its name as argv[0] and its own arguments after it.
  if (mode == "globals")
    return check_globals(argc - 1, argv + 1);
  if (mode == "quasistatic")
    return check_quasistatic(argc - 1, argv + 1);
  if (mode == "stability")
    return check_stability(argc - 1, argv + 1);
  if (mode == "softening")
    return check_damage(argc - 1, argv + 1);
  std::cout << "usage: perideal_check globals|quasistatic|stability|softening ARGUMENTS..." << std::endl;
  return 2;
}
