#include <perideal/base/input.h>

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
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

  namespace
  {
    /// What a path that is not a regular file is, for messages.
    std::string
    kind_of_file(const std::filesystem::file_status &status)
    {
      using std::filesystem::file_type;
      switch (status.type())
        {
          case file_type::directory:
            return "a directory";
          case file_type::fifo:
            return "a FIFO (named pipe)";
          case file_type::character:
            return "a character device";
          case file_type::block:
            return "a block device";
          case file_type::socket:
            return "a socket";
          default:
            return "not a regular file";
        }
    }

    /// A place in a parameter file, "file:line".
    std::string
    place(const std::string &file, const unsigned int line)
    {
      return file + ":" + std::to_string(line);
    }

    /**
     * A light pre-scan of a parameter file before deal.II reads it, with
     * deal.II 9.4's own line rules (ParameterHandler::parse_input and
     * scan_line): each line trimmed; a line ending in a backslash continues on
     * the next (checked before comments are cut); '#' starts a comment (no
     * escape); tabs become spaces; then 'set NAME = VALUE', 'subsection NAME',
     * 'end' or 'include FILE' (keywords all lower or all upper case). Names
     * are compared as deal.II compares them: trimmed, inner whitespace kept
     * (deal.II does not fold it: 'Bulk  modulus' is another, undeclared key).
     * An include's file is opened as deal.II opens it: the path as written,
     * relative to the directory the run starts in.
     *
     * It refuses what deal.II would read silently or never finish: a file
     * (or an included file) that is not a regular file (a FIFO blocks every
     * rank in the open), an include cycle (deal.II recurses until the stack
     * overflows), a key set twice in the same subsection and a subsection
     * entered twice at the same level (deal.II keeps the last value). At the
     * first line deal.II would reject itself (a malformed line, an unbalanced
     * 'end', an include that cannot be opened) the scan stops and leaves the
     * message to deal.II, so its messages are unchanged.
     */
    class PreScan
    {
    public:
      /// Scans @p file; false if it stopped at a line deal.II will reject.
      bool
      scan(const std::string &file)
      {
        std::ifstream in(file);
        if (!in)
          return false;
        check_encoding(in, file);
        const std::size_t depth = path.size();
        chain.push_back({file, canonical(file), depth});
        std::string       raw, logical;
        unsigned int      line_n = 0, logical_n = 0;
        bool              continued = false;
        while (std::getline(in, raw))
          {
            ++line_n;
            if (!continued)
              logical_n = line_n;
            raw = dealii::Utilities::trim(raw);
            if (!raw.empty() && raw.back() == '\\')
              {
                raw.pop_back();
                logical += raw;
                continued = true;
                continue;
              }
            logical += raw;
            continued = false;
            if (!scan_line(logical, file, logical_n))
              return false;
            logical.clear();
          }
        if (continued && !scan_line(logical, file, line_n))
          return false;
        // deal.II requires every file to leave the subsections it entered.
        if (path.size() != depth)
          return false;
        chain.pop_back();
        return true;
      }

    private:
      struct Open
      {
        std::string           name;
        std::filesystem::path canonical;
        std::size_t           depth; // subsections open when it was included
      };
      struct Level
      {
        std::string                                             name;
        std::map<std::string, std::pair<std::string, unsigned>> entries, subsections;
      };

      std::vector<Open>  chain; // the files being read, outermost first
      std::vector<Level> path{Level()};

      /**
       * deal.II reads bytes: a byte-order mark, which some editors (Notepad)
       * put at the start of a file, becomes part of the first line, which then
       * "could not be parsed" with the mark invisible in the message; UTF-16
       * puts a zero byte in every character. Named here instead.
       */
      static void
      check_encoding(std::ifstream &in, const std::string &file)
      {
        char              bytes[4] = {};
        in.read(bytes, sizeof(bytes));
        const std::string head(bytes, in.gcount());
        in.clear();
        in.seekg(0);
        const auto starts = [&head](const std::string &mark) { return head.compare(0, mark.size(), mark) == 0; };
        AssertThrow(!starts("\xEF\xBB\xBF"),
                    dealii::ExcMessage(place(file, 1) +
                                       ": the file starts with a UTF-8 byte-order mark (the invisible "
                                       "bytes EF BB BF), which deal.II reads as part of the first line: "
                                       "save the file as UTF-8 without BOM (or ASCII), e.g. "
                                       "sed -i '1s/^\\xEF\\xBB\\xBF//' " + file));
        AssertThrow(!starts("\xFF\xFE") && !starts("\xFE\xFF") && head.find('\0') == std::string::npos,
                    dealii::ExcMessage(place(file, 1) +
                                       ": the file is UTF-16 (or holds zero bytes), and deal.II reads "
                                       "parameter files as ASCII or UTF-8: save it as UTF-8 without BOM, "
                                       "e.g. iconv -f UTF-16 -t UTF-8 " + file));
      }

      static std::filesystem::path
      canonical(const std::string &file)
      {
        std::error_code error;
        const auto      path = std::filesystem::weakly_canonical(file, error);
        return error ? std::filesystem::absolute(file, error) : path;
      }

      std::string
      full_name(const std::string &name) const
      {
        std::string s;
        for (std::size_t i = 1; i < path.size(); ++i)
          s += path[i].name + "/";
        return s + name;
      }

      bool
      scan_line(std::string line, const std::string &file, const unsigned int line_n)
      {
        const auto starts = [&line](const char *lower, const char *upper) {
          return dealii::Utilities::match_at_string_start(line, lower) ||
                 dealii::Utilities::match_at_string_start(line, upper);
        };
        if (line.find('#') != std::string::npos)
          line.erase(line.find('#'));
        std::replace(line.begin(), line.end(), '\t', ' ');
        line = dealii::Utilities::trim(line);
        if (line.empty())
          return true;
        if (starts("subsection ", "SUBSECTION "))
          {
            const std::string name = dealii::Utilities::trim(line.substr(11));
            const auto [it, added] =
              path.back().subsections.emplace(name, std::make_pair(file, line_n));
            AssertThrow(added,
                        dealii::ExcMessage(
                          "subsection " + full_name(name) + " is given twice, at " +
                          place(it->second.first, it->second.second) + " and at " +
                          place(file, line_n) +
                          " (the second would silently replace values of the first): "
                          "merge them into one"));
            path.push_back(Level{name, {}, {}});
            return true;
          }
        if (starts("end", "END"))
          {
            // deal.II: an 'end' with more on the line, or one leaving a
            // subsection the file did not enter (unbalanced at its end).
            if (!dealii::Utilities::trim(line.substr(3)).empty() || path.size() <= chain.back().depth)
              return false;
            path.pop_back();
            return true;
          }
        if (starts("set ", "SET "))
          {
            const std::size_t equal = line.find('=');
            if (equal == std::string::npos)
              return false;
            const std::string name = dealii::Utilities::trim(line.substr(4, equal - 4));
            const auto [it, added] =
              path.back().entries.emplace(name, std::make_pair(file, line_n));
            AssertThrow(added,
                        dealii::ExcMessage(
                          full_name(name) + " is set twice, at " +
                          place(it->second.first, it->second.second) + " and at " +
                          place(file, line_n) +
                          " (the second would silently replace the first): keep one"));
            return true;
          }
        if (starts("include ", "INCLUDE "))
          {
            std::string name = line.substr(7);
            name.erase(0, name.find_first_not_of(' '));
            std::error_code error;
            const auto      status = std::filesystem::status(name, error);
            if (name.empty() || !std::filesystem::exists(status))
              return false; // deal.II names the file it cannot open
            AssertThrow(std::filesystem::is_regular_file(status),
                        dealii::ExcMessage(place(file, line_n) + ": the included file '" +
                                           name + "' is " + kind_of_file(status) +
                                           ", not a regular file: include a parameter file"));
            const auto target = canonical(name);
            for (std::size_t i = 0; i < chain.size(); ++i)
              if (chain[i].canonical == target)
                {
                  std::string cycle;
                  for (std::size_t j = i; j < chain.size(); ++j)
                    cycle += chain[j].name + " -> ";
                  AssertThrow(false,
                              dealii::ExcMessage(
                                place(file, line_n) + ": 'include " + name +
                                "' makes an include cycle (" + cycle + name +
                                "): a file must not include itself, directly or "
                                "through other files; remove the include"));
                }
            return scan(name);
          }
        return false; // deal.II reports the line it cannot parse
      }
    };
  } // namespace

  void
  check_parameter_file(const std::string &filename)
  {
    // Not opened before its type is known: opening a FIFO blocks every rank.
    std::error_code error;
    const auto      status = std::filesystem::status(filename, error);
    AssertThrow(std::filesystem::exists(status),
                dealii::ExcMessage("cannot open the parameter file '" +
                                   filename + "'"));
    AssertThrow(std::filesystem::is_regular_file(status),
                dealii::ExcMessage("the parameter file '" + filename + "' is " +
                                   kind_of_file(status) +
                                   ", not a regular file: give the path of a .prm file"));
    PreScan().scan(filename);
  }

  void
  parse_input_file(ParameterHandler  &prm,
                   const std::string &filename,
                   const bool         strict)
  {
    check_parameter_file(filename);
    std::ifstream in(filename);
    AssertThrow(in.good(),
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
