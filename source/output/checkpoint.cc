// Checkpoint directories: written atomically, read back with every check a
// restart needs (checkpoint.h).

#include <perideal/base/format.h>
#include <perideal/output/checkpoint.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    // 2: checkpoint.txt ends with the CRC-32 of the text before it (format 1,
    // without it, is not read). 3: the output series holds the Exodus
    // file's, a quasistatic solver its load step's start (issue 42).
    constexpr unsigned int format_version = 3;
    const std::string      marker         = "PeriDeal checkpoint ";

    std::string
    rank_file(const std::string &directory, const unsigned int rank)
    {
      std::ostringstream name;
      name << directory << "/rank-" << std::setw(4) << std::setfill('0') << rank << ".bin";
      return name.str();
    }

    std::uint32_t
    crc_of(const std::string &bytes)
    {
      // zlib's crc32 takes at most 4 GiB at a time.
      uLong             value = crc32(0L, Z_NULL, 0);
      const std::size_t chunk = std::size_t(1) << 30;
      for (std::size_t at = 0; at < bytes.size(); at += chunk)
        value = crc32(value, reinterpret_cast<const Bytef *>(bytes.data() + at),
                      static_cast<uInt>(std::min(chunk, bytes.size() - at)));
      return static_cast<std::uint32_t>(value);
    }

    /// The first non-empty problem of any rank (the lowest rank's), on every
    /// rank. Collective.
    std::string
    first_problem(const std::string &local, const MPI_Comm comm)
    {
      for (const std::string &p : Utilities::MPI::all_gather(comm, local))
        if (!p.empty())
          return p;
      return "";
    }

    /// "Section/Subsection/Key" -> value of deal.II's PRM text (as
    /// ParameterHandler::print_parameters writes it).
    std::map<std::string, std::string>
    parameter_map(const std::string &text)
    {
      std::map<std::string, std::string> values;
      std::vector<std::string>           path;
      std::istringstream                 in(text);
      std::string                        line, pending;
      while (std::getline(in, line))
        {
          const std::size_t first = line.find_first_not_of(" \t");
          if (first == std::string::npos || line[first] == '#')
            continue;
          line = pending + line.substr(first);
          if (!line.empty() && line.back() == '\\')
            {
              pending = line.substr(0, line.size() - 1);
              continue;
            }
          pending.clear();
          while (!line.empty() && (line.back() == ' ' || line.back() == '\t' || line.back() == '\r'))
            line.pop_back();
          if (line.rfind("subsection ", 0) == 0)
            path.push_back(line.substr(11));
          else if (line == "end")
            {
              if (!path.empty())
                path.pop_back();
            }
          else if (line.rfind("set ", 0) == 0)
            {
              const std::size_t eq = line.find('=');
              if (eq == std::string::npos)
                continue;
              // "set Key = value # default: d": a value holds no '#' (the reader takes it as a comment).
              std::string key = line.substr(4, eq - 4), value = line.substr(eq + 1, line.find('#', eq) - eq - 1);
              while (!value.empty() && value.back() == ' ')
                value.pop_back();
              while (!key.empty() && key.back() == ' ')
                key.pop_back();
              value.erase(0, std::min(value.size(), value.find_first_not_of(' ')));
              std::string full;
              for (const std::string &p : path)
                full += p + "/";
              values[full + key] = value;
            }
        }
      return values;
    }

    /// What differs between the parameters of the checkpoint and of this run,
    /// outside Output (which may change), or empty.
    std::string
    parameter_differences(const std::string &there, const std::string &here, const unsigned int stage)
    {
      auto a = parameter_map(there), b = parameter_map(here);
      // The stages up to the checkpoint's must be the same; later ones may
      // be added, changed or dropped (a run continued with another impact).
      const auto stage_names = [](const std::map<std::string, std::string> &m) {
        const auto it = m.find("Solver stages/Names");
        return it == m.end() ? std::vector<std::string>() : Utilities::split_string_list(it->second, ',');
      };
      const std::vector<std::string> names_a = stage_names(a), names_b = stage_names(b);
      for (unsigned int k = 0; k < stage; ++k)
        if (k >= names_b.size() || k >= names_a.size() || names_a[k] != names_b[k])
          return "Solver stages/Names must begin with the " + std::to_string(stage) +
                 " stage(s) the checkpoint has run ('" + a["Solver stages/Names"] + "'), it is '" +
                 b["Solver stages/Names"] + "'";
      const auto drop_later = [stage](std::map<std::string, std::string> &m, const std::vector<std::string> &names) {
        m.erase("Solver stages/Names");
        for (unsigned int k = stage; k < names.size(); ++k)
          for (auto it = m.lower_bound("Solver stages/" + names[k] + "/");
               it != m.end() && it->first.rfind("Solver stages/" + names[k] + "/", 0) == 0;)
            it = m.erase(it);
      };
      drop_later(a, names_a);
      drop_later(b, names_b);
      std::vector<std::string> keys;
      for (const auto &[k, v] : a)
        keys.push_back(k);
      for (const auto &[k, v] : b)
        if (!a.count(k))
          keys.push_back(k);
      std::sort(keys.begin(), keys.end());
      std::vector<std::string> differences;
      for (const std::string &k : keys)
        {
          if (k.rfind("Output/", 0) == 0)
            continue;
          const auto ia = a.find(k), ib = b.find(k);
          const std::string va = ia == a.end() ? "(no such key)" : "'" + ia->second + "'";
          const std::string vb = ib == b.end() ? "(no such key)" : "'" + ib->second + "'";
          if (va != vb)
            differences.push_back(k + " is " + vb + " here, " + va + " in the checkpoint");
        }
      if (differences.empty())
        return "";
      std::string text;
      const std::size_t shown = std::min<std::size_t>(differences.size(), 6);
      for (std::size_t i = 0; i < shown; ++i)
        text += (i > 0 ? "; " : "") + differences[i];
      if (shown < differences.size())
        text += "; and " + std::to_string(differences.size() - shown) + " more";
      return text;
    }

    /// checkpoint.txt's text into @p header; what is wrong with it, or empty.
    std::string
    parse_header(const std::string &text, CheckpointHeader &header)
    {
      if (text.rfind(marker, 0) != 0)
        return "checkpoint.txt does not begin with '" + marker + "': not a PeriDeal checkpoint";
      header.format = static_cast<unsigned int>(std::strtoul(text.c_str() + marker.size(), nullptr, 10));
      if (header.format != format_version)
        return "checkpoint.txt is of format " + std::to_string(header.format) + ", this PeriDeal reads format " +
               std::to_string(format_version) + " only";
      // The last line: the CRC-32 of everything before it.
      const std::string damaged = "checkpoint.txt is damaged (truncated or changed: ";
      const std::size_t last    = text.size() < 2 ? std::string::npos : text.rfind('\n', text.size() - 2);
      if (text.empty() || text.back() != '\n' || last == std::string::npos || text.compare(last + 1, 6, "crc32 ") != 0)
        return damaged + "it does not end with its CRC-32)";
      char             *end   = nullptr;
      const std::string value = text.substr(last + 7, text.size() - last - 8);
      const unsigned long stored = std::strtoul(value.c_str(), &end, 10);
      if (value.empty() || *end != '\0' || stored != crc_of(text.substr(0, last + 1)))
        return damaged + "its CRC-32 check fails)";

      std::istringstream in(text.substr(0, last + 1));
      std::string        word, line;
      std::getline(in, line);
      bool        ok = true;
      std::string time_text;
      ok = ok && (in >> word >> header.step) && word == "step";
      ok = ok && (in >> word >> time_text) && word == "time";
      if (ok)
        header.time = std::strtod(time_text.c_str(), nullptr);
      std::string start_word, start_text;
      ok = ok && (in >> word >> header.stage >> start_word >> start_text) && word == "stage" && start_word == "start";
      if (ok)
        header.stage_start = std::strtod(start_text.c_str(), nullptr);
      ok = ok && (in >> word >> header.ranks) && word == "ranks" && header.ranks > 0 && header.ranks < 1u << 24;
      for (unsigned int r = 0; ok && r < header.ranks; ++r)
        {
          unsigned int  number = 0;
          std::string   w2, w3;
          std::uint64_t size = 0;
          std::uint32_t c    = 0;
          ok = (in >> word >> number >> w2 >> size >> w3 >> c) && word == "rank" && number == r && w2 == "bytes" &&
               w3 == "crc32";
          header.sizes.push_back(size);
          header.crc32s.push_back(c);
        }
      ok = ok && (in >> word) && word == "parameters";
      if (!ok)
        return "checkpoint.txt is damaged (its CRC-32 holds, but its lines are not those of a checkpoint)";
      std::getline(in, line);
      std::ostringstream rest;
      rest << in.rdbuf();
      header.parameters = rest.str();
      return "";
    }

    namespace fs = std::filesystem;

    /// Why @p dir must not be replaced by a checkpoint, or empty: it is
    /// missing, empty, or a checkpoint PeriDeal wrote (checkpoint.txt
    /// beginning with the marker, and rank-NNNN.bin files, nothing else).
    std::string
    not_a_checkpoint(const fs::path &dir)
    {
      std::error_code ec;
      const auto      status = fs::symlink_status(dir, ec);
      if (!fs::exists(status))
        return "";
      if (!fs::is_directory(status))
        return "is not a directory";
      bool        has_marker = false;
      std::string other;
      for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
        {
          const std::string name = it->path().filename().string();
          const bool regular = it->is_regular_file(ec) && !it->is_symlink(ec);
          const bool rank_file = name.size() >= 13 && name.rfind("rank-", 0) == 0 &&
                                 name.compare(name.size() - 4, 4, ".bin") == 0 &&
                                 name.find_first_not_of("0123456789", 5) == name.size() - 4;
          if (regular && name == "checkpoint.txt")
            {
              std::ifstream in(it->path(), std::ios::binary);
              std::string   start(marker.size(), '\0');
              in.read(start.data(), std::streamsize(start.size()));
              has_marker = in && start == marker;
            }
          else if (!(regular && rank_file) && other.empty())
            other = name;
        }
      if (ec)
        return "cannot be read (" + ec.message() + ")";
      if (!other.empty())
        return "holds '" + other + "', which no PeriDeal checkpoint holds";
      if (!has_marker && !fs::is_empty(dir, ec))
        return "holds files but no checkpoint.txt beginning with '" + marker + "'";
      return "";
    }

    /// The absolute form of @p path with '.', '..' and the symbolic links of
    /// its existing part resolved.
    fs::path
    resolved(const std::string &path)
    {
      std::error_code ec;
      const fs::path  p = fs::weakly_canonical(fs::absolute(path), ec);
      return ec ? fs::absolute(path).lexically_normal() : p;
    }

    /// True if @p inner is @p outer or lies inside it.
    bool
    is_within(const fs::path &inner, const fs::path &outer)
    {
      auto i = inner.begin(), o = outer.begin();
      for (; o != outer.end() && !o->empty(); ++o, ++i)
        if (i == inner.end() || *i != *o)
          return false;
      return true;
    }
    std::string
    read_file(const std::string &name, bool &ok)
    {
      // Sized first: one copy of the file in memory, not a growing stream's.
      std::ifstream in(name, std::ios::binary | std::ios::ate);
      ok = bool(in);
      if (!ok)
        return "";
      std::string text(static_cast<std::size_t>(in.tellg()), '\0');
      in.seekg(0);
      in.read(text.data(), std::streamsize(text.size()));
      ok = bool(in);
      return text;
    }
  } // namespace

  // ------------------------------------------------------------ reader

  void
  CheckpointReader::expect(const bool condition, const std::string &what) const
  {
    AssertThrow(condition, ExcMessage("the checkpoint file '" + file + "' does not fit this run (section '" +
                                      current + "'): " + what));
  }

  void
  CheckpointReader::section(const std::string &name)
  {
    std::string found;
    get(found);
    expect(found == name, "expected the section '" + name + "', found '" + found.substr(0, 40) + "'");
    current = name;
  }

  std::size_t
  CheckpointReader::count(const std::size_t element_size)
  {
    const std::uint64_t n = get<std::uint64_t>();
    expect(element_size == 0 || n <= (bytes.size() - position) / element_size,
           "a count of " + std::to_string(n) + " entries runs past the end of the file");
    return n;
  }

  void
  CheckpointReader::take(void *data, const std::size_t size)
  {
    expect(size <= bytes.size() - position, "the file ends early");
    std::memcpy(data, bytes.data() + position, size);
    position += size;
  }

  // ------------------------------------------------------------ parameters

  void
  CheckpointParameters::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Checkpoint");
    prm.declare_entry("Frequency", "0", Patterns::Integer(0),
                      "Write a checkpoint every this many steps (load steps); 0: none. pd_app --restart DIR "
                      "params.prm continues from it, bit for bit as the run would have gone on (doc/restart.md).");
    prm.declare_entry("Minutes", "0", Patterns::Double(0),
                      "Write a checkpoint at the end of the first step after this many minutes of wall-clock "
                      "time since the run started or the last checkpoint; 0: none.");
    prm.declare_entry("On signal", "true", Patterns::Bool(),
                      "On SIGTERM or SIGINT (a batch system's time limit, Ctrl-C) the run finishes its step, "
                      "writes it and a checkpoint, and stops with exit code 128 + the signal.");
    prm.declare_entry("Directory", "", Patterns::Anything(),
                      "The checkpoint's directory, replaced whole by each new checkpoint (the previous one is "
                      "kept until the new one is complete). Empty: <Output/Directory>/<base name>.checkpoint.");
    prm.leave_subsection();
  }

  void
  CheckpointParameters::parse_parameters(ParameterHandler &prm, const std::string &output_directory,
                                         const std::string &base_name)
  {
    prm.enter_subsection("Checkpoint");
    frequency = prm.get_integer("Frequency");
    minutes   = prm.get_double("Minutes");
    on_signal = prm.get_bool("On signal");
    directory = prm.get("Directory");
    prm.leave_subsection();
    if (directory.empty())
      directory = output_directory + "/" + base_name + ".checkpoint";
    while (directory.size() > 1 && directory.back() == '/')
      directory.pop_back();
  }

  // ------------------------------------------------------------ write

  CheckpointWriter::CheckpointWriter(const std::string &directory_, const MPI_Comm comm)
    : directory(directory_)
    , comm(comm)
  {
    const std::string partial = directory + ".partial";
    std::string       problem;
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      {
        // Set-up refused what is not a checkpoint (check_checkpoint_directory);
        // checked again here, where it is removed.
        std::error_code ec;
        problem = not_a_checkpoint(partial);
        if (!problem.empty())
          problem = "'" + partial + "' " + problem + ": not removed, no checkpoint written";
        else
          {
            fs::remove_all(partial, ec);
            fs::create_directories(partial, ec);
            // The marker first: a .partial left by a stopped run is known as ours.
            std::ofstream marker_file(partial + "/checkpoint.txt", std::ios::binary);
            marker_file << marker << format_version << " (being written)\n";
            marker_file.close();
            if (ec || !fs::is_directory(partial) || !marker_file)
              problem = "cannot create '" + partial + "'" + (ec ? " (" + ec.message() + ")" : std::string());
          }
      }
    problem = Utilities::MPI::broadcast(comm, problem, 0);
    AssertThrow(problem.empty(), ExcMessage("Output/Checkpoint/Directory: " + problem));
    file = rank_file(partial, Utilities::MPI::this_mpi_process(comm));
    out  = std::fopen(file.c_str(), "wb");
    failed = out == nullptr;
    crc    = static_cast<std::uint32_t>(crc32(0L, Z_NULL, 0));
    buffer.reserve(buffer_size);
  }

  CheckpointWriter::~CheckpointWriter()
  {
    if (out)
      std::fclose(out);
  }

  void
  CheckpointWriter::write(const void *data, const std::size_t size)
  {
    const Bytef *bytes = static_cast<const Bytef *>(data);
    for (std::size_t at = 0; at < size; at += buffer_size) // zlib's crc32 takes an uInt
      crc = static_cast<std::uint32_t>(crc32(crc, bytes + at, static_cast<uInt>(std::min(buffer_size, size - at))));
    if (!failed && std::fwrite(data, 1, size, out) != size)
      failed = true;
    written += size;
  }

  void
  CheckpointWriter::flush()
  {
    write(buffer.data(), buffer.size());
    buffer.clear();
  }

  double
  CheckpointWriter::finish(const std::string &parameters, const unsigned int step, const double time,
                           const unsigned int stage, const double stage_start)
  {
    const unsigned int rank = Utilities::MPI::this_mpi_process(comm);
    const std::string  partial = directory + ".partial", previous = directory + ".previous";
    flush();
    if (out && std::fclose(out) != 0)
      failed = true;
    out = nullptr;
    std::string problem = failed ? "cannot write '" + file + "' (is the disk full?)" : "";
    problem             = first_problem(problem, comm);
    AssertThrow(problem.empty(), ExcMessage("Output/Checkpoint: " + problem));

    const std::vector<std::uint64_t> sizes = Utilities::MPI::gather(comm, written, 0);
    const std::vector<std::uint32_t> crcs  = Utilities::MPI::gather(comm, crc, 0);
    double                           total = 0;
    if (rank == 0)
      {
        std::ostringstream header;
        header << "PeriDeal checkpoint " << format_version << "\n"
               << "step " << step << "\n"
               << "time " << std::hexfloat << time << std::defaultfloat << "\n"
               << "stage " << stage << " start " << std::hexfloat << stage_start << std::defaultfloat << "\n"
               << "ranks " << sizes.size() << "\n";
        for (unsigned int r = 0; r < sizes.size(); ++r)
          {
            header << "rank " << r << " bytes " << sizes[r] << " crc32 " << crcs[r] << "\n";
            total += sizes[r];
          }
        header << "parameters\n" << parameters;
        std::string body = header.str();
        if (body.back() != '\n')
          body += '\n';
        // Covered by its own CRC-32: a truncated header is named damaged.
        body += "crc32 " + std::to_string(crc_of(body)) + "\n";
        std::ofstream text(partial + "/checkpoint.txt", std::ios::binary);
        text << body;
        text.close();
        std::error_code ec;
        const std::string foreign = not_a_checkpoint(directory), foreign_previous = not_a_checkpoint(previous);
        if (!text)
          problem = "cannot write '" + partial + "/checkpoint.txt'";
        else if (!foreign.empty() || !foreign_previous.empty())
          problem = "'" + (foreign.empty() ? previous : directory) + "' " +
                    (foreign.empty() ? foreign_previous : foreign) + ": not replaced; the checkpoint is in '" +
                    partial + "'";
        else
          {
            // The previous checkpoint stays until the new one has its name.
            fs::remove_all(previous, ec);
            if (fs::exists(directory))
              fs::rename(directory, previous, ec);
            if (!ec)
              fs::rename(partial, directory, ec);
            if (ec)
              problem = "cannot rename '" + partial + "' to '" + directory + "' (" + ec.message() + ")";
            else
              fs::remove_all(previous, ec);
          }
      }
    problem = Utilities::MPI::broadcast(comm, problem, 0);
    AssertThrow(problem.empty(), ExcMessage("Output/Checkpoint/Directory: " + problem));
    return Utilities::MPI::broadcast(comm, total, 0);
  }

  // ------------------------------------------------------------ set-up check

  void
  check_checkpoint_directory(const std::string &directory, const std::string &output_directory,
                             const std::string &parameter_file, const std::string &parameters, const MPI_Comm comm)
  {
    std::string problem;
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      {
        // What the run reads: the parameter file and every file a key names.
        std::vector<std::pair<std::string, std::string>> inputs{{"the parameter file", parameter_file}};
        for (const auto &[key, value] : parameter_map(parameters))
          {
            const std::string name = key.substr(key.rfind('/') + 1);
            if (!value.empty() && (name == "File" || (name.size() > 5 && name.compare(name.size() - 5, 5, " file") == 0)))
              inputs.emplace_back(key, value);
          }
        for (const char *suffix : {"", ".partial", ".previous"})
          {
            const std::string folder = directory + suffix;
            const fs::path    here   = resolved(folder);
            std::string       why;
            if (is_within(resolved(output_directory), here))
              why = "is or contains the output directory '" + output_directory + "' (Output/Directory)";
            for (const auto &[what, file] : inputs)
              if (why.empty() && is_within(resolved(file).parent_path(), here))
                why = "is or contains the folder of " + what + " '" + file + "'";
            if (why.empty())
              why = not_a_checkpoint(folder);
            if (!why.empty() && problem.empty())
              problem = "'" + folder + "' " + why + ". A checkpoint replaces its folder whole (and " + directory +
                        ".partial, " + directory + ".previous): name a new or empty folder, or an earlier checkpoint";
          }
      }
    problem = Utilities::MPI::broadcast(comm, problem, 0);
    AssertThrow(problem.empty(), ExcMessage("Output/Checkpoint/Directory: " + problem));
  }

  // ------------------------------------------------------------ read

  CheckpointStage
  checkpoint_stage(const std::string &directory, const MPI_Comm comm)
  {
    CheckpointStage found;
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      {
        bool             ok = false;
        CheckpointHeader header;
        const std::string text = read_file(directory + "/checkpoint.txt", ok);
        if (ok && parse_header(text, header).empty())
          found = {header.stage, header.stage_start};
      }
    found.stage = Utilities::MPI::broadcast(comm, found.stage, 0);
    found.start = Utilities::MPI::broadcast(comm, found.start, 0);
    return found;
  }

  std::pair<CheckpointReader, CheckpointHeader>
  read_checkpoint(const std::string &directory_given, const std::string &parameters, const MPI_Comm comm)
  {
    namespace fs               = std::filesystem;
    const unsigned int rank    = Utilities::MPI::this_mpi_process(comm);
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
    std::string        directory = directory_given;
    while (directory.size() > 1 && directory.back() == '/')
      directory.pop_back();
    const std::string where = "--restart '" + directory + "': ";

    // Rank 0 reads and checks the header; every rank learns it.
    std::string      problem, header_text;
    CheckpointHeader header;
    if (rank == 0)
      {
        bool ok     = false;
        header_text = read_file(directory + "/checkpoint.txt", ok);
        if (!ok)
          {
            if (fs::is_directory(directory + ".previous"))
              problem = "no complete checkpoint there; the run stopped while replacing it: the previous one, '" +
                        directory + ".previous', is complete: restart from it";
            else if (!fs::exists(directory))
              problem = "no such directory";
            else
              problem = "no checkpoint.txt there: not a checkpoint, or one that was never completed";
          }
      }
    problem = Utilities::MPI::broadcast(comm, problem, 0);
    AssertThrow(problem.empty(), ExcMessage(where + problem));
    header_text = Utilities::MPI::broadcast(comm, header_text, 0);
    {
      const std::string damaged = parse_header(header_text, header);
      AssertThrow(damaged.empty(), ExcMessage(where + damaged));
    }
    AssertThrow(header.ranks == n_ranks,
                ExcMessage(where + "the checkpoint was written by " + std::to_string(header.ranks) +
                           (header.ranks == 1 ? " rank" : " ranks") + ", this run has " + std::to_string(n_ranks) +
                           ": the rank count must match (mpirun -np " +
                           std::to_string(header.ranks) + ")"));
    const std::string differences = parameter_differences(header.parameters, parameters, header.stage);
    AssertThrow(differences.empty(),
                ExcMessage(where + "the checkpoint was written with other parameters (only Output may change): " +
                           differences));

    bool              ok   = false;
    const std::string name = rank_file(directory, rank);
    std::string       bytes = read_file(name, ok);
    if (!ok)
      problem = "'" + name + "' is missing: the checkpoint is incomplete";
    else if (bytes.size() != header.sizes[rank])
      problem = "'" + name + "' has " + std::to_string(bytes.size()) + " bytes, checkpoint.txt says " +
                std::to_string(header.sizes[rank]) + ": the checkpoint is damaged";
    else if (crc_of(bytes) != header.crc32s[rank])
      problem = "'" + name + "' fails its CRC-32 check: the checkpoint is damaged";
    problem = first_problem(problem, comm);
    AssertThrow(problem.empty(), ExcMessage(where + problem));
    return {CheckpointReader(std::move(bytes), name), header};
  }
} // namespace perideal
