// perideal_check MODE ARGUMENTS...: the checks of a pd_app run's globals CSV
// and output, run by the test runner (tests/tools/run.sh check) after pd_app.
// The modes and their arguments are described in check_globals.cc (globals),
// check_quasistatic.cc (quasistatic), check_stability.cc (stability),
// check_damage.cc (softening), check_contact.cc (contact) and check_fields.cc (fields: the field files).
// Exit code: 0 every check passed, 1 a check failed, 2 bad arguments or input.

#include "check.h"

#include <iostream>
#include <string>

// The one mode that reads field files (check.h declares the others).
int
check_fields(int argc, char *argv[]);

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
  if (mode == "contact")
    return check_contact(argc - 1, argv + 1);
  if (mode == "fields")
    return check_fields(argc - 1, argv + 1);
  std::cout << "usage: perideal_check globals|quasistatic|stability|softening|contact|fields ARGUMENTS..." << std::endl;
  return 2;
}
