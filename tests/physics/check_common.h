#pragma once
// What the checker programs of the pd_app tests share (check_quasistatic,
// tests/stability/check_stability): a failure count, the PASS/FAIL line and
// the verdict, command-line values, the globals CSV as rows of named columns.
// Serial; no MPI.

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

  /// Prints "NAME = VALUE  (BOUND)  PASS|FAIL", VALUE with @p digits
  /// significant digits, and counts a failure.
  inline void
  check(const std::string &name, const double value, const bool ok, const std::string &bound, const int digits)
  {
    std::cout << name << " = " << str(value, digits) << "  (" << bound << ")  " << (ok ? "PASS" : "FAIL") << "\n";
    if (!ok)
      ++failures;
  }

  /// Prints the verdict line and returns the exit code (0: all passed, 1: a
  /// check failed).
  inline int
  finish()
  {
    std::cout << (failures == 0 ? "ALL PASSED" : std::to_string(failures) + " CHECK(S) FAILED") << std::endl;
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
