#pragma once
// Checkpoints and restarts (doc/restart.md).
//
// A checkpoint is a directory: one binary file per rank with everything that
// rank's parts keep from one step to the next (u, v, f, a of every DoF, the
// bond damage, the models' committed history, the conditions' own state, the
// record of the run, the output series so far and the integrator's place),
// and checkpoint.txt (rank 0): the format, the step and time, the rank count,
// each rank file's size and CRC-32, and the run's parameters as read. The
// mesh and the bonds are not stored: a restart builds them from the same
// parameter file on the same number of ranks, which gives the same points,
// partition and bonds, and checks that it did (points, bonds, DoFs and a hash
// of the reference positions per rank). Everything a step recomputes from
// that state (stage fields, contact lists, tangents) is recomputed, so the
// continued run repeats the uninterrupted one bit for bit.
//
// Written whole or not at all: rank 0 marks DIR.partial as a checkpoint
// being written (checkpoint.txt with its first line only), every rank writes
// into it, rank 0 writes checkpoint.txt whole last (its last line the CRC-32
// of the rest), then DIR becomes DIR.previous, DIR.partial
// becomes DIR and DIR.previous is removed; a run stopped in between leaves
// DIR or DIR.previous complete, and a restart says which to use. Only a
// checkpoint (checkpoint.txt beginning with "PeriDeal checkpoint ", and
// rank-NNNN.bin files, nothing else) or an empty folder is ever removed or
// replaced: set-up refuses any other (check_checkpoint_directory()).
//
// Each part writes and reads its own state (save/load), in one order, with
// named sections, so that a reader out of step names the section.

#include <perideal/base/input.h>

#include <deal.II/base/mpi.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <deque>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace perideal
{
  /// What one rank's parts write into a checkpoint: straight to this
  /// rank's file in DIR.partial through a 1 MiB buffer (no copy of the
  /// state in memory), with a running CRC-32.
  class CheckpointWriter
  {
  public:
    /// Makes @p directory.partial (rank 0) and opens this rank's file there. Collective.
    CheckpointWriter(const std::string &directory, const MPI_Comm comm);
    ~CheckpointWriter();
    /// Closes the files, writes checkpoint.txt with @p parameters, @p step and
    /// @p time, and gives the checkpoint its name (see above); returns the
    /// bytes of all ranks' files. Collective.
    /// @p stage and @p stage_start: the running solver (Solver stages) and
    /// its start time; @p step counts the steps of every solver.
    double
    finish(const std::string &parameters, const unsigned int step, const double time, const unsigned int stage,
           const double stage_start);

    /// A named section: the reader checks it is where it expects it.
    void
    section(const std::string &name)
    {
      put(name);
    }
    template <typename T>
    void
    put(const T &value)
    {
      static_assert(std::is_trivially_copyable_v<T>, "plain values only");
      append(&value, sizeof(T));
    }
    template <typename T>
    void
    put(const std::vector<T> &values)
    {
      static_assert(std::is_trivially_copyable_v<T>, "plain values only");
      put<std::uint64_t>(values.size());
      append(values.data(), values.size() * sizeof(T));
    }
    void
    put(const std::string &text)
    {
      put<std::uint64_t>(text.size());
      append(text.data(), text.size());
    }
    void
    put(const std::vector<std::string> &texts)
    {
      put<std::uint64_t>(texts.size());
      for (const std::string &t : texts)
        put(t);
    }
    template <typename A, typename B>
    void
    put(const std::deque<std::pair<A, B>> &pairs)
    {
      put_pairs(pairs);
    }
    template <typename A, typename B>
    void
    put(const std::vector<std::pair<A, B>> &pairs)
    {
      put_pairs(pairs);
    }
    /// The locally owned entries of a distributed vector.
    template <typename Vector>
    void
    put_owned(const Vector &v)
    {
      put<std::uint64_t>(v.locally_owned_size());
      append(v.begin(), v.locally_owned_size() * sizeof(double));
    }

  private:
    /// A container of pairs: its size, then each pair (std::pair is not
    /// trivially copyable).
    template <typename Pairs>
    void
    put_pairs(const Pairs &pairs)
    {
      put<std::uint64_t>(pairs.size());
      for (const auto &p : pairs)
        {
          put(p.first);
          put(p.second);
        }
    }
    void
    append(const void *data, const std::size_t size)
    {
      if (buffer.size() + size > buffer_size)
        flush();
      if (size >= buffer_size)
        write(data, size);
      else
        buffer.append(static_cast<const char *>(data), size);
    }
    void
    flush();
    void
    write(const void *data, const std::size_t size);

    static constexpr std::size_t buffer_size = std::size_t(1) << 20;
    std::string                  directory, file;
    MPI_Comm                     comm;
    std::FILE                   *out = nullptr;
    std::string                  buffer;
    std::uint64_t                written = 0;
    std::uint32_t                crc     = 0;
    bool                         failed  = false;
  };

  /// Reads back what a CheckpointWriter wrote; an Error names the file and
  /// the section where the bytes do not fit.
  class CheckpointReader
  {
  public:
    CheckpointReader(std::string bytes, std::string file)
      : bytes(std::move(bytes))
      , file(std::move(file))
    {}
    void
    section(const std::string &name);
    template <typename T>
    void
    get(T &value)
    {
      static_assert(std::is_trivially_copyable_v<T>, "plain values only");
      take(&value, sizeof(T));
    }
    template <typename T>
    T
    get()
    {
      T value;
      get(value);
      return value;
    }
    template <typename T>
    void
    get(std::vector<T> &values)
    {
      static_assert(std::is_trivially_copyable_v<T>, "plain values only");
      values.resize(count(sizeof(T)));
      take(values.data(), values.size() * sizeof(T));
    }
    void
    get(std::string &text)
    {
      text.resize(count(1));
      take(text.data(), text.size());
    }
    void
    get(std::vector<std::string> &texts)
    {
      texts.resize(count(sizeof(std::uint64_t)));
      for (std::string &t : texts)
        get(t);
    }
    template <typename A, typename B>
    void
    get(std::deque<std::pair<A, B>> &pairs)
    {
      get_pairs(pairs);
    }
    template <typename A, typename B>
    void
    get(std::vector<std::pair<A, B>> &pairs)
    {
      get_pairs(pairs);
    }
    /// Into the locally owned entries of @p v, which must have as many;
    /// the ghosts are not touched.
    template <typename Vector>
    void
    get_owned(Vector &v, const std::string &what)
    {
      const std::uint64_t n = get<std::uint64_t>();
      expect(n == v.locally_owned_size(), what + " has " + std::to_string(v.locally_owned_size()) +
                                            " entries on this rank, " + std::to_string(n) + " in the checkpoint");
      take(v.begin(), n * sizeof(double));
    }
    /// Stops with an Error naming the file and the section if @p condition fails.
    void
    expect(const bool condition, const std::string &what) const;
    /// True once every byte is read.
    bool
    at_end() const
    {
      return position == bytes.size();
    }

  private:
    template <typename Pairs>
    void
    get_pairs(Pairs &pairs)
    {
      pairs.resize(count(1));
      for (auto &p : pairs)
        {
          get(p.first);
          get(p.second);
        }
    }
    /// A count written before @p element_size bytes each, checked against what is left.
    std::size_t
    count(const std::size_t element_size);
    void
    take(void *data, const std::size_t size);

    std::string bytes, file, current = "(start)";
    std::size_t position = 0;
  };

  /// Output/Checkpoint.
  struct CheckpointParameters
  {
    static void
    declare_parameters(ParameterHandler &prm);
    void
    parse_parameters(ParameterHandler &prm, const std::string &output_directory, const std::string &base_name);

    unsigned int frequency = 0;    // every this many steps; 0: none
    double       minutes   = 0;    // after this many minutes of wall-clock time since the last; 0: none
    bool         on_signal = true; // on SIGTERM and SIGINT
    std::string  directory;        // where (a directory, replaced whole at every checkpoint)
    bool
    any() const
    {
      return frequency > 0 || minutes > 0 || on_signal;
    }
  };

  /// What the restart check compares: the parameters of both runs and the
  /// discretization each rank built.
  struct CheckpointHeader
  {
    unsigned int               format = 0, ranks = 0, step = 0, stage = 0;
    double                     time = 0, stage_start = 0;
    std::string                parameters;
    std::vector<std::uint64_t> sizes;  // per rank file
    std::vector<std::uint32_t> crc32s; // per rank file
  };

  /// The solver (Solver stages) a checkpoint was written in and that
  /// solver's start time; stage 0 if checkpoint.txt cannot be read (then
  /// read_checkpoint() says why). Collective.
  struct CheckpointStage
  {
    unsigned int stage = 0;
    double       start = 0;
  };
  CheckpointStage
  checkpoint_stage(const std::string &directory, const MPI_Comm comm);

  /// Refuses (an Error naming Output/Checkpoint/Directory) a checkpoint
  /// directory @p directory whose writing would delete what PeriDeal did not
  /// write: it, DIR.partial or DIR.previous exists and is not empty nor a
  /// checkpoint (checkpoint.txt beginning with "PeriDeal checkpoint " and
  /// rank-NNNN.bin files only), or is or contains @p output_directory or the
  /// folder of a file the run reads (@p parameter_file, every key of
  /// @p parameters named File or "... file"). Writes nothing. Collective.
  void
  check_checkpoint_directory(const std::string &directory, const std::string &output_directory,
                             const std::string &parameter_file, const std::string &parameters, const MPI_Comm comm);

  /// Reads the checkpoint in @p directory: checks that it is complete and
  /// whole (sizes, CRC-32), written by as many ranks as this run has, and
  /// by the same parameters as @p parameters (every key outside Output and
  /// the stages after the checkpoint's, which may be added or changed; an
  /// Error names the keys that differ). Returns this rank's bytes and
  /// the header. Collective.
  std::pair<CheckpointReader, CheckpointHeader>
  read_checkpoint(const std::string &directory, const std::string &parameters, const MPI_Comm comm);
} // namespace perideal
