#pragma once
// The checker library of the test suite: what perideal_check (the checks of
// a pd_app run's globals CSV and standard output: check_globals.cc,
// check_quasistatic.cc, check_stability.cc, check_damage.cc) and the C++ test programs
// (tests/physics/harness.h) share: the "NAME = VALUE  (BOUND)  PASS|FAIL"
// line, a failure count and the verdict, command-line values, the globals
// CSV as rows of named columns. Serial; no MPI.

#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace check_common
{
  using Row = std::map<std::string, double>;

  inline unsigned int failures = 0;

  /// @p v with @p digits significant digits.
  inline std::string
  str(const double v, const int digits = 3)
  {
    std::ostringstream o;
    o << std::setprecision(digits) << v;
    return o.str();
  }

  /// "NAME = VALUE  (BOUND)  PASS|FAIL", VALUE with @p digits significant digits.
  inline std::string
  check_line(const std::string &name, const double value, const bool ok, const std::string &bound,
             const int digits)
  {
    return name + " = " + str(value, digits) + "  (" + bound + ")  " + (ok ? "PASS" : "FAIL");
  }

  /// The last line of a check program's output after @p n_failures failed checks.
  inline std::string
  verdict(const unsigned int n_failures)
  {
    return n_failures == 0 ? "ALL PASSED" : std::to_string(n_failures) + " CHECK(S) FAILED";
  }

  /// Prints check_line() and counts a failure.
  inline void
  check(const std::string &name, const double value, const bool ok, const std::string &bound, const int digits)
  {
    std::cout << check_line(name, value, ok, bound, digits) << "\n";
    if (!ok)
      ++failures;
  }

  /// Prints the verdict line and returns the exit code (0: all passed, 1: a
  /// check failed).
  inline int
  finish()
  {
    std::cout << verdict(failures) << std::endl;
    return failures == 0 ? 0 : 1;
  }

  /// The next command-line value for option @p option (advancing @p a).
  inline std::string
  next_argument(const int argc, char **argv, int &a, const std::string &option)
  {
    if (a + 1 >= argc)
      throw std::runtime_error(option + " needs a value");
    return argv[++a];
  }

  /// The rows of a CSV file with a header line; a line with fewer entries
  /// than the header is an error.
  inline std::vector<Row>
  read_rows(const std::string &file)
  {
    std::ifstream in(file);
    if (!in)
      throw std::runtime_error("cannot open " + file);
    std::string              line;
    std::vector<std::string> header;
    std::getline(in, line);
    std::stringstream h(line);
    for (std::string c; std::getline(h, c, ',');)
      header.push_back(c);
    std::vector<Row> rows;
    while (std::getline(in, line))
      {
        std::stringstream s(line);
        Row               row;
        std::string       c;
        for (unsigned int k = 0; k < header.size() && std::getline(s, c, ','); ++k)
          row[header[k]] = std::strtod(c.c_str(), nullptr);
        if (row.size() != header.size())
          throw std::runtime_error("short line in " + file + ": " + line);
        rows.push_back(row);
      }
    return rows;
  }
} // namespace check_common

// The modes of perideal_check (perideal_check.cc), each with its own
// arguments after the mode's name (argv[0]).
int
check_globals(int argc, char *argv[]);
int
check_quasistatic(int argc, char *argv[]);
int
check_stability(int argc, char *argv[]);
int
check_damage(int argc, char *argv[]);
int
check_contact(int argc, char *argv[]);
