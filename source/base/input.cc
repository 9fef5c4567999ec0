#include <perideal/base/input.h>

#include <deal.II/base/utilities.h>

#include <filesystem>
#include <fstream>
#include <set>

namespace perideal
{
  std::vector<std::string>
  split_names(const std::string &list, const std::string &where)
  {
    std::vector<std::string> names;
    std::set<std::string>    seen;
    for (const auto &raw : dealii::Utilities::split_string_list(list, ','))
      {
        const std::string name = dealii::Utilities::trim(raw);
        if (name.empty())
          continue;
        AssertThrow(seen.insert(name).second,
                    dealii::ExcMessage(where + ": the name '" + name +
                                       "' appears twice"));
        names.push_back(name);
      }
    return names;
  }

  dealii::Point<3>
  get_point(ParameterHandler &prm, const std::string &key)
  {
    const auto v = dealii::Utilities::string_to_double(dealii::Utilities::split_string_list(prm.get(key), ','));
    return dealii::Point<3>(v[0], v[1], v[2]);
  }

  void
  declare_names_entry(ParameterHandler &prm, const std::string &what)
  {
    prm.declare_entry("Names",
                      "",
                      dealii::Patterns::Anything(),
                      "Comma separated names of the " + what +
                        "; each name has a subsection of its own here.");
  }

  void
  parse_input_file(ParameterHandler  &prm,
                   const std::string &filename,
                   const bool         strict)
  {
    std::ifstream in(filename);
    AssertThrow(in.good() && std::filesystem::is_regular_file(filename),
                dealii::ExcMessage("cannot open the parameter file '" +
                                   filename + "'"));
    prm.parse_input(in, filename, "", /*skip_undefined=*/!strict);
  }

  void
  require_positive(const double value, const std::string &path)
  {
    AssertThrow(value > 0,
                dealii::ExcMessage(path + " must be positive, got " +
                                   dealii::Utilities::to_string(value)));
  }
} // namespace perideal
