#pragma once
// Field output (one .vtu per rank and output step, a .pvtu per step, a .pvd
// series) and the CSV of global quantities. Field files are written whole or
// not at all: each goes to a temporary name and is renamed when complete (the
// CSV grows by one appended row per output step); a step's
// .vtu pieces get their names only when every rank has written its own, then
// the .pvtu and the .pvd follow (Simulation::write_output appends the CSV row
// after them), so a run killed at any moment leaves the .pvd listing complete
// steps only, no piece of another step, and a CSV never ahead of the .pvd.
// Output/Field format = hdf5 writes HDF5 files and an XDMF series instead
// (xdmf.cc), with the same ordering: a step's .h5 gets its name when
// complete, then the .xdmf lists it. Output/Field format = exodus writes
// Peridigm's output, an Exodus II file that grows by a time step per output
// step (exodus_output.cc).

#include <perideal/base/input.h>
#include <perideal/material/field_store.h>
#include <perideal/output/checkpoint.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/lac/vector.h>

#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace perideal
{
  class OutputWriter
  {
  public:
    /// Declared inside subsection "Output"; @p model_fields: the fields the
    /// registered models offer (model_output_fields()). Output/Variables'
    /// names and documentation come from output_variables() (output_field.h).
    static void
    declare_parameters(ParameterHandler &prm, const std::vector<PointField> &model_fields);
    void
    parse_parameters(ParameterHandler &prm);

    bool
    wants(const std::string &variable) const
    {
      return variables.count(variable) > 0;
    }

    /// Step 0, every Frequency-th step and the last one; none if Frequency is 0.
    bool
    is_field_step(const unsigned int step, const unsigned int n_steps) const
    {
      return frequency > 0 && (step % frequency == 0 || step == n_steps);
    }
    /// The same for the globals CSV with Globals frequency (0: Frequency).
    bool
    is_globals_step(const unsigned int step, const unsigned int n_steps) const
    {
      const unsigned int f = globals_frequency > 0 ? globals_frequency : frequency;
      return globals && f > 0 && (step % f == 0 || step == n_steps);
    }
    /// A step that writes fields or globals.
    bool
    is_output_step(const unsigned int step, const unsigned int n_steps) const
    {
      return is_field_step(step, n_steps) || is_globals_step(step, n_steps);
    }

    /// Keeps the text of @p prm, the run's parameters as read (every key,
    /// defaults included, in deal.II's PRM format) from @p file, for
    /// initialize() and create_files().
    void
    keep_parameters(const ParameterHandler &prm, const std::string &file);

    /// Checks that the output directory and the checkpoint's can be used
    /// (check_checkpoint_directory()) and clears the series; writes nothing.
    /// Collective.
    void
    initialize(const MPI_Comm comm);

    /// Creates the output directory and writes the kept parameters there as
    /// <base name>.parameters.prm (rank 0; pd_app on that file repeats the
    /// run): once every check of the set-up (a restart's too) has passed,
    /// before the first output. Collective.
    void
    create_files(const MPI_Comm comm);

    /// A field constant per cell: 1 component (a scalar), 3 (a vector) or 9
    /// (a 3x3 tensor, row-major), each one value per active cell.
    struct CellField
    {
      std::string                               name;
      std::vector<const dealii::Vector<double> *> components;
    };
    using VectorField = std::pair<std::string,
                                  const dealii::LinearAlgebra::distributed::Vector<double> *>;

    /// This rank's part of the Exodus file's mesh (Field format = exodus):
    /// each PD point a node with a SPHERE element, each continuum cell a
    /// HEX8 on its vertices, in the element block of its block.
    struct ExodusMesh
    {
      struct Block
      {
        std::string name;
        int         id        = 0;     // the element block's id
        bool        continuum = false; // HEX8 elements; otherwise SPHERE
      };
      std::vector<Block> blocks;
      // The owned PD points (not the virtual ones): the cell whose DoFs and
      // cell field entries hold the point's values, the reference position
      // (dim numbers each), the block and the id (1-based, rank-independent).
      std::vector<dealii::DoFHandler<3>::active_cell_iterator> point_cells;
      std::vector<double>                                      point_X;
      std::vector<unsigned int>                                point_block;
      std::vector<std::int64_t>                                point_id;
      std::uint64_t point_ids_end = 0; // the point ids are below it; the continuum's nodes' and cells' above
      // The owned cells of continuum blocks and their blocks.
      std::vector<dealii::DoFHandler<3>::active_cell_iterator> fe_cells;
      std::vector<unsigned int>                                fe_block;
    };
    using GlobalsRow = std::vector<std::pair<std::string, double>>;

    /// Writes one output step of @p cell_fields and @p vector_fields (DG0
    /// vectors on @p dof_handler) on the locally owned cells whose
    /// @p written_cells entry (by active cell index) is true: the cells that
    /// hold a point or FE DoFs, not the cells no block claims. A vector or
    /// tensor cell field becomes one array of 3 or 9 components in the
    /// files, as ParaView reads them. Field format = exodus writes
    /// @p exodus_mesh instead of the cells, and @p globals (the step's
    /// globals row, if it has one) as global variables. Collective.
    void
    write_fields(const dealii::DoFHandler<3>    &dof_handler,
                 const std::vector<bool>        &written_cells,
                 const std::vector<CellField>   &cell_fields,
                 const std::vector<VectorField> &vector_fields,
                 const unsigned int              step,
                 const double                    time,
                 const MPI_Comm                  comm,
                 const ExodusMesh               *exodus_mesh = nullptr,
                 const GlobalsRow               &globals     = {});

    /// Appends a row to <directory>/<base name>.globals.csv (rank 0 writes;
    /// the first row of a run or a restart writes the file whole, with the
    /// rows of the series so far).
    void
    write_globals(const std::vector<std::pair<std::string, double>> &row,
                  const MPI_Comm                                    comm);

    /// The series so far: .pvd records, XDMF grids and globals rows (checkpoint.h).
    void
    save(CheckpointWriter &out) const;
    void
    load(CheckpointReader &in);
    /// The kept parameters (keep_parameters()).
    const std::string &
    parameter_text() const
    {
      return parameters;
    }

    std::string           directory = "output";
    std::string           base_name = "run";
    unsigned int          frequency = 0;
    unsigned int          globals_frequency = 0; // 0: frequency
    unsigned int          globals_digits    = 10; // significant digits of the globals CSV
    std::set<std::string> variables;
    bool                  globals = true;
    bool                  fragments = false; // <base name>.fragments.csv at field steps
    bool                  double_precision = false; // Field precision = double: Float64 arrays
    bool                  hdf5             = false; // Field format = hdf5: .h5 files and an .xdmf series
    bool                  exodus           = false; // Field format = exodus: <base name>.e
    bool                  exodus_per_rank  = false; // Exodus files = per rank: <base name>.e.N.r
    CheckpointParameters  checkpoint;               // Output/Checkpoint

  private:
    /// write_fields() for Field format = hdf5 (xdmf.cc): one <base
    /// name>_<step>.h5 of cell-centred datasets for all ranks (MPI-IO), the
    /// mesh in <base name>_<step>.mesh.h5 when the written cells change (the
    /// first output step), <base name>.xdmf listing the steps. Collective.
    void
    write_hdf5(const dealii::DoFHandler<3>    &dof_handler,
               const std::vector<bool>        &written_cells,
               const std::vector<CellField>   &cell_fields,
               const std::vector<VectorField> &vector_fields,
               const unsigned int              step,
               const double                    time,
               const MPI_Comm                  comm);

    /// write_fields() for Field format = exodus (exodus_output.cc): a time
    /// step of <base name>.e (or this rank's <base name>.e.N.r), created at
    /// the first output step and again, as <base name>.e-s0002 and so on,
    /// when the written mesh changes. Collective.
    void
    write_exodus(const ExodusMesh               &mesh,
                 const std::vector<CellField>   &cell_fields,
                 const std::vector<VectorField> &vector_fields,
                 const GlobalsRow               &globals,
                 const double                    time,
                 const MPI_Comm                  comm);
    /// The name of the series' current file on this rank.
    std::string
    exodus_file_name(const MPI_Comm comm) const;

    std::string                                 parameters, parameter_file;
    std::vector<std::pair<double, std::string>> pvd_records;
    std::vector<std::string>                    csv_lines;
    bool csv_on_disk = false; // the file holds csv_lines but the last: append
    // The XDMF series: a <Grid> per written step; the mesh file those of the
    // last mesh refer to, its global cell and node counts, and this rank's
    // written cells (active cell indices, in the file's order).
    std::vector<std::string>  xdmf_grids;
    std::string               mesh_file;
    std::uint64_t             mesh_cells_total = 0, mesh_nodes_total = 0;
    std::vector<unsigned int> mesh_cells;
    // The Exodus series: its files so far (the current one's number), the
    // time steps in the current one, this rank's mesh in it (points, then
    // continuum cells, by active cell index) and its global variables.
    unsigned int              exodus_files = 0;
    unsigned int              exodus_steps = 0;
    std::vector<unsigned int> exodus_cells;
    std::vector<std::string>  exodus_globals;
  };

  /// The longest file name (path included) Open MPI 4.1's MPI_File_open
  /// takes: 245 characters abort the process (xdmf.cc opens a longer path
  /// from its directory).
  constexpr std::size_t mpi_io_name_limit = 244;

  /// The locally owned cells of @p dof_handler whose @p written_cells entry
  /// (by active cell index) is true, in their order, for the writers that lay
  /// out hexahedra themselves; another cell stops with "@p writer writes
  /// hexahedral cells only".
  std::vector<dealii::DoFHandler<3>::active_cell_iterator>
  written_hexahedra(const dealii::DoFHandler<3> &dof_handler,
                    const std::vector<bool>     &written_cells,
                    const std::string           &writer);

  /// Writes @p text to @p filename through a temporary file and a rename.
  void
  write_file_atomically(const std::string &filename, const std::string &text);

  /// The same; returns what went wrong instead of throwing (empty: written).
  std::string
  try_write_file_atomically(const std::string &filename, const std::string &text);
} // namespace perideal
