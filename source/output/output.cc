#include <perideal/output/output.h>
#include <perideal/output/output_field.h>

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/utilities.h>
#include <deal.II/numerics/data_out.h>

#include <zlib.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include <unistd.h>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    /// DataOut whose cell data may form vectors and tensors. deal.II 9.4
    /// writes cell data as scalars only; the ranges of consecutive cell data
    /// components that form one are added to the ranges of the DoF data here,
    /// where the VTU and PVTU writers look for them (as Particles::DataOut
    /// does), so each becomes one array of 3 or 9 components.
    class CellDataOut : public DataOut<3>
    {
    public:
      /// Adds @p fields as cell data, after every DoF data vector.
      void
      add_cell_fields(const std::vector<OutputWriter::CellField> &fields)
      {
        for (const auto &f : fields)
          {
            const unsigned int n = f.components.size();
            if (n == 1)
              add_data_vector(*f.components[0], f.name, DataOut<3>::type_cell_data);
            else
              {
                for (unsigned int c = 0; c < n; ++c)
                  add_data_vector(*f.components[c], f.name + "_" + std::to_string(c), DataOut<3>::type_cell_data);
                groups.emplace_back(n_cell_components,
                                    n_cell_components + n - 1,
                                    f.name,
                                    n == 9 ? DataComponentInterpretation::component_is_part_of_tensor :
                                             DataComponentInterpretation::component_is_part_of_vector);
              }
            n_cell_components += n;
          }
      }

    protected:
      std::vector<std::tuple<unsigned int, unsigned int, std::string,
                             DataComponentInterpretation::DataComponentInterpretation>>
      get_nonscalar_data_ranges() const override
      {
        auto ranges = DataOut<3>::get_nonscalar_data_ranges();
        // The cell data's components come after the DoF data's.
        const unsigned int first = get_dataset_names().size() - n_cell_components;
        for (const auto &[begin, last, name, kind] : groups)
          ranges.emplace_back(first + begin, first + last, name, kind);
        return ranges;
      }

    private:
      unsigned int n_cell_components = 0;
      std::vector<std::tuple<unsigned int, unsigned int, std::string,
                             DataComponentInterpretation::DataComponentInterpretation>>
        groups;
    };

    std::string
    base64(const unsigned char *data, const std::size_t n)
    {
      static const char *const digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
      std::string              text;
      text.reserve(4 * ((n + 2) / 3));
      for (std::size_t k = 0; k < n; k += 3)
        {
          const unsigned int b0 = data[k], b1 = k + 1 < n ? data[k + 1] : 0, b2 = k + 2 < n ? data[k + 2] : 0;
          const unsigned int w  = (b0 << 16) | (b1 << 8) | b2;
          text += digits[(w >> 18) & 63];
          text += digits[(w >> 12) & 63];
          text += k + 1 < n ? digits[(w >> 6) & 63] : '=';
          text += k + 2 < n ? digits[w & 63] : '=';
        }
      return text;
    }

    /// One binary DataArray body as deal.II 9.4 writes it (VTK's
    /// vtkZLibDataCompressor, UInt32 header): the header {1 block, its size,
    /// the last block's size, the compressed size} in base64, then the zlib
    /// block in base64.
    template <typename T>
    std::string
    compressed_array(const std::vector<T> &values)
    {
      const auto   bytes = reinterpret_cast<const Bytef *>(values.data());
      const uLong  size  = values.size() * sizeof(T);
      uLongf       packed_size = compressBound(size);
      std::vector<Bytef> packed(packed_size);
      AssertThrow(compress2(packed.data(), &packed_size, bytes, size, Z_BEST_SPEED) == Z_OK,
                  ExcMessage("zlib cannot compress a field array"));
      const std::uint32_t header[4] = {1, std::uint32_t(size), std::uint32_t(size), std::uint32_t(packed_size)};
      return base64(reinterpret_cast<const unsigned char *>(header), sizeof(header)) +
             base64(packed.data(), packed_size);
    }

    template <typename T>
    void
    write_array(std::ostream &out, const std::string &type, const std::string &name, const unsigned int components,
                const std::vector<T> &values)
    {
      out << "<DataArray type=\"" << type << "\"" << (name.empty() ? "" : " Name=\"" + name + "\"")
          << (components > 1 ? " NumberOfComponents=\"" + std::to_string(components) + "\"" : "")
          << " format=\"binary\">\n"
          << compressed_array(values) << "\n</DataArray>\n";
    }

    /// The hexahedra of the written cells as a VTU piece with Float64 data,
    /// laid out as deal.II's DataOut lays out its patches (8 vertices per
    /// cell, not shared; every field as point data: a cell field takes its
    /// cell's value at the 8 vertices, a nodal one its vertex values).
    std::string
    double_precision_vtu(const DoFHandler<3>                           &dof_handler,
                         const std::vector<bool>                       &written_cells,
                         const std::vector<OutputWriter::CellField>   &cell_fields,
                         const std::vector<OutputWriter::VectorField> &vector_fields)
    {
      // deal.II's vertex order to VTK_HEXAHEDRON's.
      static constexpr unsigned int vtk_order[8] = {0, 1, 3, 2, 4, 5, 7, 6};
      const auto cells = written_hexahedra(dof_handler, written_cells, "Output/Field precision = double");
      const std::size_t   n_points = 8 * cells.size();
      std::vector<double> points;
      points.reserve(3 * n_points);
      for (const auto &cell : cells)
        for (const unsigned int v : vtk_order)
          for (unsigned int d = 0; d < 3; ++d)
            points.push_back(cell->vertex(v)[d]);
      std::vector<std::int32_t> connectivity(n_points), offsets(cells.size());
      std::vector<std::uint8_t> types(cells.size(), 12); // VTK_HEXAHEDRON
      for (std::size_t k = 0; k < n_points; ++k)
        connectivity[k] = std::int32_t(k);
      for (std::size_t c = 0; c < cells.size(); ++c)
        offsets[c] = std::int32_t(8 * (c + 1));

      std::ostringstream out;
      out << "<?xml version=\"1.0\" ?>\n"
          << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" compressor=\"vtkZLibDataCompressor\" "
             "byte_order=\"LittleEndian\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\""
          << n_points << "\" NumberOfCells=\"" << cells.size() << "\">\n<Points>\n";
      write_array(out, "Float64", "", 3, points);
      out << "</Points>\n<Cells>\n";
      write_array(out, "Int32", "connectivity", 1, connectivity);
      write_array(out, "Int32", "offsets", 1, offsets);
      write_array(out, "UInt8", "types", 1, types);
      out << "</Cells>\n<PointData>\n";
      std::vector<double>                  values;
      std::vector<types::global_dof_index> dofs;
      for (const auto &[name, vector] : vector_fields)
        {
          values.clear();
          for (const auto &cell : cells)
            {
              const FiniteElement<3> &fe = cell->get_fe();
              dofs.resize(fe.n_dofs_per_cell());
              cell->get_dof_indices(dofs);
              for (const unsigned int v : vtk_order)
                for (unsigned int d = 0; d < 3; ++d)
                  // DG0: the cell's one value per component; FE_Q: the
                  // vertex's (FE_Q numbers its vertex DoFs first).
                  values.push_back(dofs.empty() ? 0.0 :
                                                  (*vector)(dofs[fe.component_to_system_index(d, fe.degree == 0 ? 0 : v)]));
            }
          write_array(out, "Float64", name, 3, values);
        }
      for (const auto &f : cell_fields)
        {
          values.clear();
          for (const auto &cell : cells)
            for (unsigned int v = 0; v < 8; ++v)
              for (const auto *component : f.components)
                values.push_back((*component)[cell->active_cell_index()]);
          write_array(out, "Float64", f.name, f.components.size(), values);
        }
      out << "</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
      return out.str();
    }

    /// The .pvtu of double_precision_vtu()'s pieces.
    std::string
    double_precision_pvtu(const std::vector<OutputWriter::CellField>   &cell_fields,
                          const std::vector<OutputWriter::VectorField> &vector_fields,
                          const std::vector<std::string>               &pieces)
    {
      std::ostringstream out;
      out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\" "
             "byte_order=\"LittleEndian\">\n<PUnstructuredGrid GhostLevel=\"0\">\n<PPointData>\n";
      for (const auto &f : vector_fields)
        out << "<PDataArray type=\"Float64\" Name=\"" << f.first << "\" NumberOfComponents=\"3\" format=\"binary\"/>\n";
      for (const auto &f : cell_fields)
        out << "<PDataArray type=\"Float64\" Name=\"" << f.name << "\""
            << (f.components.size() > 1 ? " NumberOfComponents=\"" + std::to_string(f.components.size()) + "\"" : "")
            << " format=\"binary\"/>\n";
      out << "</PPointData>\n<PPoints>\n<PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n</PPoints>\n";
      for (const auto &piece : pieces)
        out << "<Piece Source=\"" << piece << "\"/>\n";
      out << "</PUnstructuredGrid>\n</VTKFile>\n";
      return out.str();
    }
  } // namespace

  void
  OutputWriter::declare_parameters(ParameterHandler &prm, const std::vector<PointField> &model_fields)
  {
    // The valid names and their documentation from the registered fields and
    // the models'; consecutive names of one documentation share it.
    const std::vector<OutputVariable> variables = output_variables(model_fields);
    std::string                       selection, documentation;
    for (unsigned int k = 0; k < variables.size(); ++k)
      {
        const bool shared = k > 0 && variables[k - 1].documentation == variables[k].documentation;
        selection += (k == 0 ? "" : "|") + variables[k].name;
        documentation += (shared ? ", " : " ") + variables[k].name;
        if (k + 1 == variables.size() || variables[k + 1].documentation != variables[k].documentation)
          documentation += ": " + variables[k].documentation;
      }
    prm.declare_entry("Directory", "output", Patterns::Anything(),
                      "Where output goes; created if missing. Every run (not --dry-run) first writes "
                      "<base name>.parameters.prm there: all its parameters, defaults included, in this "
                      "format; pd_app on that file, started in the same directory, repeats the run.");
    prm.declare_entry("Base name", "run", Patterns::Anything(),
                      "Files are <base name>_<step>.<rank>.vtu, <base name>_<step>.pvtu, "
                      "<base name>.pvd, <base name>.globals.csv and <base name>.parameters.prm.");
    prm.declare_entry("Frequency", "0", Patterns::Integer(0),
                      "Write every this many steps, plus the first and the last step. "
                      "0: write nothing during the run (the summary is still printed).");
    prm.declare_entry("Variables", "Displacement, Damage", Patterns::MultipleSelection(selection),
                      "Fields written as cell data (constant per point; vectors and tensors as "
                      "arrays of 3 and 9 components, row-major); only these are computed. A model's "
                      "field needs a block of that model. Empty: no field files, only the globals CSV." +
                        documentation);
    prm.declare_entry("Globals frequency", "0", Patterns::Integer(0),
                      "Write a globals row every this many steps (plus the first and the last); 0: "
                      "with the fields (Frequency). A fine history (reaction force, crack tip probes) "
                      "without field files at every row.");
    prm.declare_entry("Globals digits", "10", Patterns::Integer(6, std::numeric_limits<double>::max_digits10),
                      "Significant digits of the values in the globals CSV; 17: every digit of a double (a "
                      "conservation check to round-off reads them back exactly).");
    prm.declare_entry("Write globals", "true", Patterns::Bool(),
                      "Write <base name>.globals.csv with step, time, kinetic_energy, "
                      "strain_energy, broken_bonds (bonds broken, each pair of points once; the set-up "
                      "report counts directed bonds, two per pair), max_damage and more, a row per "
                      "output step.");
    prm.declare_entry("Field precision", "float", Patterns::Selection("float|double"),
                      "float: the field files' arrays are Float32 (deal.II's writer; about 7 significant "
                      "digits). double: Float64, every digit of a double (a verification that reads the "
                      "fields back), in the same format (zlib-compressed VTU pieces, a .pvtu, the .pvd); "
                      "the files are about twice as large.");
    prm.declare_entry("Field format", "vtu", Patterns::Selection("vtu|hdf5|exodus"),
                      "vtu: a zlib-compressed .vtu piece per rank and step, a .pvtu per step, the .pvd series "
                      "(values at the cells' vertices: nodal fields of FE cells as they are). hdf5, for runs of "
                      "millions of points: one <base name>_<step>.h5 per step for all ranks (MPI-IO), the mesh "
                      "once in <base name>_<step>.mesh.h5 (again only if the written cells change), and "
                      "<base name>.xdmf, the series ParaView opens (XDMF Reader). Every field is cell-centred: "
                      "a point's value, an FE cell's nodal fields at its centre. Uncompressed; Field precision "
                      "applies to the fields and the node coordinates. exodus: Peridigm's output, "
                      "<base name>.e (Exodus II), a time step per output step: each point a node (at its "
                      "reference position) with a SPHERE element in its block's element block, each FE cell "
                      "a HEX8; vector fields as nodal variables (DisplacementX, ...), the other fields as "
                      "element variables (Damage; a tensor's XX, XY, ...), the globals row as global variables "
                      "at the output steps that write one; see Exodus files. A new file <base name>.e-s0002 "
                      "(and so on) starts if the written cells change.");
    prm.declare_entry("Exodus files", "joined", Patterns::Selection("joined|per rank"),
                      "Field format = exodus on several ranks. joined: one <base name>.e, which scripts and "
                      "SEACAS' tools read as it is; the ranks write their parts into it in turn (no rank holds "
                      "more than its own), so its output steps take longer on many ranks. per rank: each rank "
                      "writes <base name>.e.N.r (N ranks, r its number), as Peridigm does in parallel; "
                      "ParaView opens the pieces as one, and the ranks write at once.");
    prm.declare_entry("Fragments", "false", Patterns::Bool(),
                      "Write <base name>.fragments.csv at every field output step (Frequency): a row per "
                      "fragment (the pieces the intact bonds hold together, numbered in the order of their "
                      "smallest point index, the same on any number of ranks) with its points, mass, centre-of-"
                      "mass velocity and kinetic energy. The field Fragment (Variables) gives each point its "
                      "fragment's number.");
    CheckpointParameters::declare_parameters(prm);
  }

  void
  OutputWriter::parse_parameters(ParameterHandler &prm)
  {
    directory = prm.get("Directory");
    base_name = prm.get("Base name");
    frequency = prm.get_integer("Frequency");
    globals_frequency = prm.get_integer("Globals frequency");
    globals_digits    = prm.get_integer("Globals digits");
    globals   = prm.get_bool("Write globals");
    fragments = prm.get_bool("Fragments");
    double_precision = prm.get("Field precision") == "double";
    hdf5             = prm.get("Field format") == "hdf5";
    exodus           = prm.get("Field format") == "exodus";
    exodus_per_rank  = prm.get("Exodus files") == "per rank";
    checkpoint.parse_parameters(prm, directory, base_name);
    variables.clear();
    for (const auto &v : Utilities::split_string_list(prm.get("Variables"), ','))
      if (!v.empty())
        variables.insert(v);
    AssertThrow(!base_name.empty() && base_name.find('/') == std::string::npos,
                ExcMessage("Output/Base name must be a plain file name, got '" +
                           base_name + "'"));
  }

  std::vector<DoFHandler<3>::active_cell_iterator>
  written_hexahedra(const DoFHandler<3> &dof_handler, const std::vector<bool> &written_cells, const std::string &writer)
  {
    std::vector<DoFHandler<3>::active_cell_iterator> cells;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && written_cells[cell->active_cell_index()])
        {
          AssertThrow(cell->reference_cell() == ReferenceCells::Hexahedron,
                      ExcMessage(writer + " writes hexahedral cells only"));
          cells.push_back(cell);
        }
    return cells;
  }

  std::string
  try_write_file_atomically(const std::string &filename, const std::string &text)
  {
    // Per process: runs started in one directory (the test suite's error
    // cases) may write the same file at once; the last rename wins, whole.
    const std::string tmp = filename + "." + std::to_string(::getpid()) + ".tmp";
    {
      std::ofstream out(tmp, std::ios::binary);
      out << text;
      out.close();
      if (!out)
        return "cannot write the file '" + tmp + "'";
    }
    if (std::rename(tmp.c_str(), filename.c_str()) != 0)
      return "cannot rename '" + tmp + "' to '" + filename + "'";
    return "";
  }

  void
  write_file_atomically(const std::string &filename, const std::string &text)
  {
    const std::string problem = try_write_file_atomically(filename, text);
    AssertThrow(problem.empty(), ExcMessage(problem));
  }

  void
  OutputWriter::keep_parameters(const ParameterHandler &prm, const std::string &file)
  {
    parameter_file = file;
    std::ostringstream out;
    prm.print_parameters(out, ParameterHandler::PRM);
    parameters = out.str();
  }

  void
  OutputWriter::save(CheckpointWriter &out) const
  {
    out.section("output series");
    out.put(pvd_records);
    out.put(csv_lines);
    out.put(xdmf_grids);
    out.put(mesh_file);
    out.put(mesh_cells_total);
    out.put(mesh_nodes_total);
    out.put(mesh_cells);
    out.section("exodus series");
    out.put(exodus_files);
    out.put(exodus_steps);
    out.put(exodus_cells);
    out.put(exodus_globals);
  }

  void
  OutputWriter::load(CheckpointReader &in)
  {
    in.section("output series");
    in.get(pvd_records);
    in.get(csv_lines);
    csv_on_disk = false;
    in.get(xdmf_grids);
    in.get(mesh_file);
    in.get(mesh_cells_total);
    in.get(mesh_nodes_total);
    in.get(mesh_cells);
    in.section("exodus series");
    in.get(exodus_files);
    in.get(exodus_steps);
    in.get(exodus_cells);
    in.get(exodus_globals);
  }

  void
  OutputWriter::initialize(const MPI_Comm comm)
  {
    // Checks only: a run refused later (a restart's checkpoint) must leave
    // every file as it was; create_files() writes.
    std::string problem;
    if (Utilities::MPI::this_mpi_process(comm) == 0 && std::filesystem::exists(directory) &&
        !std::filesystem::is_directory(directory))
      problem = "'" + directory + "' exists and is not a directory: name another Output/Directory";
    problem = Utilities::MPI::broadcast(comm, problem, 0);
    AssertThrow(problem.empty(), ExcMessage("Output/Directory: " + problem));
    const std::string longest_hdf5_file = base_name + "_000000.mesh.h5.tmp";
    AssertThrow(!hdf5 || longest_hdf5_file.size() <= mpi_io_name_limit,
                ExcMessage("Output/Base name: the HDF5 files' names (" + longest_hdf5_file + ") have " +
                           std::to_string(longest_hdf5_file.size()) + " characters; MPI-IO takes at most " +
                           std::to_string(mpi_io_name_limit) + ": shorten the base name"));
    if (checkpoint.any())
      check_checkpoint_directory(checkpoint.directory, directory, parameter_file, parameters, comm);
    pvd_records.clear();
    csv_lines.clear();
    csv_on_disk = false;
    xdmf_grids.clear();
    mesh_file.clear();
    mesh_cells.clear();
    exodus_files = 0;
    exodus_steps = 0;
    exodus_cells.clear();
    exodus_globals.clear();
  }

  void
  OutputWriter::create_files(const MPI_Comm comm)
  {
    // Rank 0 creates it; every rank learns the outcome, so that all stop
    // alike (a throw on rank 0 alone would leave the others waiting).
    std::string problem;
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::error_code ec;
        std::filesystem::create_directories(directory, ec);
        if (ec || !std::filesystem::is_directory(directory))
          problem = "cannot create '" + directory + "'" + (ec ? " (" + ec.message() + ")" : std::string());
        else if (!parameters.empty())
          problem = try_write_file_atomically(directory + "/" + base_name + ".parameters.prm", parameters);
      }
    problem = Utilities::MPI::broadcast(comm, problem, 0);
    AssertThrow(problem.empty(), ExcMessage("Output/Directory: " + problem));
  }

  void
  OutputWriter::write_fields(const DoFHandler<3>            &dof_handler,
                             const std::vector<bool>        &written_cells,
                             const std::vector<CellField>   &cell_fields,
                             const std::vector<VectorField> &vector_fields,
                             const unsigned int              step,
                             const double                    time,
                             const MPI_Comm                  comm,
                             const ExodusMesh               *exodus_mesh,
                             const GlobalsRow               &globals_row)
  {
    if (cell_fields.empty() && vector_fields.empty())
      return;
    if (exodus)
      {
        Assert(exodus_mesh != nullptr, ExcInternalError());
        return write_exodus(*exodus_mesh, cell_fields, vector_fields, globals_row, time, comm);
      }
    if (hdf5)
      return write_hdf5(dof_handler, written_cells, cell_fields, vector_fields, step, time, comm);
    CellDataOut data_out;
    data_out.attach_dof_handler(dof_handler);
    for (const auto &f : vector_fields)
      data_out.add_data_vector(
        *f.second,
        std::vector<std::string>(3, f.first),
        DataOut<3>::type_dof_data,
        std::vector<DataComponentInterpretation::DataComponentInterpretation>(
          3, DataComponentInterpretation::component_is_part_of_vector));
    data_out.add_cell_fields(cell_fields);
    // Cells no block claims hold no point: written, they would fill the
    // mesh's whole extent with zeros around the body.
    data_out.set_cell_selection([&](const Triangulation<3>::cell_iterator &cell) {
      return cell->is_active() && cell->is_locally_owned() && written_cells[cell->active_cell_index()];
    });
    if (!double_precision) // its own writer reads the vectors
      data_out.build_patches();
    // deal.II 9.4 compresses with zlib's best compression by default: 5 s
    // per output step of 19,000 points (the disk impact example), more than
    // the steps between two outputs. Best speed writes files 10-20% larger
    // in a fraction of the time.
    DataOutBase::VtkFlags flags;
    flags.compression_level = DataOutBase::VtkFlags::best_speed;
    data_out.set_flags(flags);

    const unsigned int rank    = Utilities::MPI::this_mpi_process(comm);
    const unsigned int n_ranks = Utilities::MPI::n_mpi_processes(comm);
    const std::string  stem =
      base_name + "_" + Utilities::int_to_string(step, 6);

    // Every rank writes its piece under a temporary name; once all are
    // complete, rank 0 gives them their names, then writes the .pvtu and the
    // .pvd. A run killed at any moment leaves no piece of a step that is not
    // complete (at most .tmp files), and the .pvd lists only complete steps.
    const auto piece = [&](const unsigned int r) {
      return stem + "." + Utilities::int_to_string(r, 4) + ".vtu";
    };
    {
      std::ostringstream vtu;
      if (double_precision)
        vtu << double_precision_vtu(dof_handler, written_cells, cell_fields, vector_fields);
      else
        data_out.write_vtu(vtu);
      const std::string tmp = directory + "/" + piece(rank) + ".tmp";
      std::ofstream     out(tmp, std::ios::binary);
      out << vtu.str();
      out.close();
      AssertThrow(out, ExcMessage("cannot write the file '" + tmp + "'"));
    }
    MPI_Barrier(comm);
    if (rank == 0)
      {
        std::vector<std::string> pieces;
        for (unsigned int r = 0; r < n_ranks; ++r)
          {
            pieces.push_back(piece(r));
            const std::string name = directory + "/" + piece(r);
            AssertThrow(std::rename((name + ".tmp").c_str(), name.c_str()) == 0,
                        ExcMessage("cannot rename '" + name + ".tmp' to '" + name + "'"));
          }
        std::ostringstream pvtu;
        if (double_precision)
          pvtu << double_precision_pvtu(cell_fields, vector_fields, pieces);
        else
          data_out.write_pvtu_record(pvtu, pieces);
        write_file_atomically(directory + "/" + stem + ".pvtu", pvtu.str());

        pvd_records.emplace_back(time, stem + ".pvtu");
        std::ostringstream pvd;
        DataOutBase::write_pvd_record(pvd, pvd_records);
        write_file_atomically(directory + "/" + base_name + ".pvd", pvd.str());
      }
  }

  void
  OutputWriter::write_globals(const std::vector<std::pair<std::string, double>> &row,
                              const MPI_Comm                                    comm)
  {
    if (!globals || Utilities::MPI::this_mpi_process(comm) != 0)
      return;
    if (csv_lines.empty())
      {
        std::string header;
        for (const auto &c : row)
          header += (header.empty() ? "" : ",") + c.first;
        csv_lines.push_back(header);
      }
    std::ostringstream line;
    line << std::setprecision(globals_digits);
    for (unsigned int c = 0; c < row.size(); ++c)
      line << (c ? "," : "") << row[c].second;
    csv_lines.push_back(line.str());
    const std::string file = directory + "/" + base_name + ".globals.csv";
    if (!csv_on_disk)
      {
        // The first row of this run (or of a restart): the rows so far, whole.
        std::string text;
        for (const auto &l : csv_lines)
          text += l + "\n";
        write_file_atomically(file, text);
        csv_on_disk = true;
        return;
      }
    // Then a row at a time, appended: rewriting the file at every row made
    // a run's CSV cost grow with the square of its rows (40,000 rows: 190 s
    // of a 194 s run).
    std::ofstream out(file, std::ios::app | std::ios::binary);
    out << csv_lines.back() << '\n';
    out.close();
    AssertThrow(out, ExcMessage("cannot append to the file '" + file + "'"));
  }
} // namespace perideal
