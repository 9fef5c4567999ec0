#pragma once
// Reading a deal.II parameter file whose sections hold user-named entries
// (materials, blocks, boundary conditions, regions): the names decide which
// subsections exist, so the file is read in passes. Pass 1 finds the names,
// pass 2 the model chosen for each name, the last pass declares everything and
// parses strictly, so that a misspelled key is an error, never a silent default.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>

#include <perideal/base/registry.h>

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace perideal
{
  constexpr unsigned int dim = 3;

  using dealii::ParameterHandler;

  /// Comma separated list of names -> trimmed, non-empty names; duplicates are an error.
  std::vector<std::string>
  split_names(const std::string &list, const std::string &where);

  /// The entry @p key of the current subsection, "x, y, z", as a point.
  dealii::Point<3>
  get_point(ParameterHandler &prm, const std::string &key);

  /// Declares the names list entry "Names" in the current subsection.
  void
  declare_names_entry(ParameterHandler &prm, const std::string &what);

  /// Declares the section @p section of user-named subsections: its Names
  /// entry (@p what) and, in the subsection of each name n of @p names, what
  /// @p declare(n) declares.
  template <typename Names, typename Declare>
  void
  declare_named_section(ParameterHandler  &prm,
                        const std::string &section,
                        const std::string &what,
                        const Names       &names,
                        const Declare     &declare)
  {
    prm.enter_subsection(section);
    declare_names_entry(prm, what);
    for (const std::string &name : names)
      {
        prm.enter_subsection(name);
        declare(name);
        prm.leave_subsection();
      }
    prm.leave_subsection();
  }

  /// Checks the parameter file @p filename before deal.II reads it: a
  /// regular file (checked without opening it), no include cycle, no key set
  /// twice in a subsection, no subsection given twice at one level. Throws
  /// ExcMessage naming the file and line(s).
  void
  check_parameter_file(const std::string &filename);

  /// Reads @p filename into @p prm (after check_parameter_file). With @p strict false, keys not declared
  /// yet are skipped (an early pass). Errors name the file and the line.
  void
  parse_input_file(ParameterHandler  &prm,
                   const std::string &filename,
                   const bool         strict);

  /// Throws ExcMessage naming the key @p path if @p value is not positive.
  void
  require_positive(const double value, const std::string &path);

} // namespace perideal
