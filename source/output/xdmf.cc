// Output/Field format = hdf5: the field files as HDF5 with an XDMF series,
// for runs of millions of points. All ranks write one file per output step
// through MPI-IO, each its rows of every dataset. The values are cell-centred
// (a point's value is its cell's), so a step holds n_cells x components
// numbers per field; the mesh (unique vertices per rank, hexahedra in VTK's
// vertex order) goes to a file of its own, written again only when the
// written cells change. deal.II's write_hdf5_parallel writes 8 vertices per
// cell with nodal values, and the mesh with every step: about 8 times the
// data at 1 M points.

#include <perideal/output/output.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/fe/fe.h>

#include <hdf5.h>

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <iomanip>
#include <map>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    /// An HDF5 handle closed when it goes out of scope.
    class Handle
    {
    public:
      Handle(const hid_t id, herr_t (*close)(hid_t), const std::string &what)
        : id(id)
        , close(close)
      {
        AssertThrow(id >= 0, ExcMessage("HDF5 output: cannot " + what));
      }
      ~Handle()
      {
        close(id);
      }
      Handle(const Handle &) = delete;
      Handle &
      operator=(const Handle &) = delete;
      operator hid_t() const
      {
        return id;
      }

    private:
      hid_t id;
      herr_t (*close)(hid_t);
    };

    template <typename T>
    hid_t
    file_type()
    {
      if constexpr (std::is_same_v<T, double>)
        return H5T_IEEE_F64LE;
      else if constexpr (std::is_same_v<T, float>)
        return H5T_IEEE_F32LE;
      else
        return H5T_STD_U32LE;
    }
    template <typename T>
    hid_t
    memory_type()
    {
      if constexpr (std::is_same_v<T, double>)
        return H5T_NATIVE_DOUBLE;
      else if constexpr (std::is_same_v<T, float>)
        return H5T_NATIVE_FLOAT;
      else
        return H5T_NATIVE_UINT32;
    }

    /// Rows [first, first + rows) of the dataset @p name (total x columns)
    /// in @p file, from @p values (rows x columns). Collective: every rank
    /// calls it, with its rows (possibly none).
    template <typename T>
    void
    write_rows(const hid_t file, const std::string &name, const std::uint64_t total, const unsigned int columns,
               const std::uint64_t first, const std::vector<T> &values)
    {
      const std::uint64_t rows        = values.size() / columns;
      const hsize_t       dims[2]     = {total, columns};
      const Handle        file_space(H5Screate_simple(2, dims, nullptr), H5Sclose, "create a data space");
      // No modification times: a step written twice gives the same bytes
      // (a restart's files equal an uninterrupted run's).
      const Handle creation(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "create a property list");
      H5Pset_obj_track_times(creation, false);
      const Handle dataset(H5Dcreate2(file, name.c_str(), file_type<T>(), file_space, H5P_DEFAULT, creation,
                                      H5P_DEFAULT),
                           H5Dclose, "create the dataset '" + name + "'");
      const hsize_t start[2] = {first, 0}, count[2] = {rows, columns};
      const Handle  memory_space(H5Screate_simple(2, count, nullptr), H5Sclose, "create a data space");
      if (rows > 0)
        H5Sselect_hyperslab(file_space, H5S_SELECT_SET, start, nullptr, count, nullptr);
      else
        {
          H5Sselect_none(file_space);
          H5Sselect_none(memory_space);
        }
      const Handle transfer(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "create a property list");
      H5Pset_dxpl_mpio(transfer, H5FD_MPIO_COLLECTIVE);
      AssertThrow(H5Dwrite(dataset, memory_type<T>(), memory_space, file_space, transfer, values.data()) >= 0,
                  ExcMessage("HDF5 output: cannot write the dataset '" + name + "'"));
    }

    /// A file all ranks write at @p directory/@p file + ".tmp", renamed to
    /// @p directory/@p file by rank 0 once every rank has closed it.
    class SharedFile
    {
    public:
      SharedFile(const std::string &directory, const std::string &file, const MPI_Comm comm)
        : name(directory + "/" + file)
        , comm(comm)
      {
        const std::string temporary = file + ".tmp";
        AssertThrow(temporary.size() <= mpi_io_name_limit,
                    ExcMessage("Output/Base name: the HDF5 file '" + temporary + "' has a name of " +
                               std::to_string(temporary.size()) + " characters; MPI-IO takes at most " +
                               std::to_string(mpi_io_name_limit) + ": shorten the base name"));
        const Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "create a property list");
        H5Pset_fapl_mpio(access, comm, MPI_INFO_NULL);
        // Open MPI 4.1's MPI_File_open copies the name into a buffer of 256
        // bytes with a suffix of its own (the shared file pointer's lock
        // file): a name of 245 characters or more aborts the process
        // ("buffer overflow detected"). Opened from its directory, the file
        // is named by its own name alone.
        const bool from_directory = name.size() + 4 > mpi_io_name_limit;
        const int  here           = from_directory ? ::open(".", O_RDONLY | O_DIRECTORY) : -1;
        AssertThrow(!from_directory || (here >= 0 && ::chdir(directory.c_str()) == 0),
                    ExcMessage("HDF5 output: cannot open the directory '" + directory + "'"));
        id = H5Fcreate((from_directory ? temporary : name + ".tmp").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, access);
        if (from_directory)
          {
            const bool back = ::fchdir(here) == 0;
            ::close(here);
            AssertThrow(back, ExcMessage("HDF5 output: cannot return to the working directory"));
          }
        AssertThrow(id >= 0, ExcMessage("HDF5 output: cannot create the file '" + name + ".tmp'"));
      }
      ~SharedFile()
      {
        // Left by an error (a write that failed): closed, and the
        // incomplete file removed.
        if (id >= 0)
          {
            H5Fclose(id);
            if (Utilities::MPI::this_mpi_process(comm) == 0)
              std::remove((name + ".tmp").c_str());
          }
      }
      SharedFile(const SharedFile &) = delete;
      SharedFile &
      operator=(const SharedFile &) = delete;
      operator hid_t() const
      {
        return id;
      }
      void
      finish()
      {
        const herr_t closed = H5Fclose(id);
        id                  = -1;
        AssertThrow(closed >= 0, ExcMessage("HDF5 output: cannot close the file '" + name + ".tmp'"));
        MPI_Barrier(comm);
        if (Utilities::MPI::this_mpi_process(comm) == 0)
          AssertThrow(std::rename((name + ".tmp").c_str(), name.c_str()) == 0,
                      ExcMessage("cannot rename '" + name + ".tmp' to '" + name + "'"));
      }

    private:
      std::string name;
      MPI_Comm    comm;
      hid_t       id = -1;
    };

    /// The first row of this rank and the total over all ranks of @p rows.
    std::pair<std::uint64_t, std::uint64_t>
    rows_of_rank(const std::uint64_t rows, const MPI_Comm comm)
    {
      std::uint64_t first = 0;
      MPI_Exscan(&rows, &first, 1, MPI_UINT64_T, MPI_SUM, comm);
      if (Utilities::MPI::this_mpi_process(comm) == 0)
        first = 0; // MPI_Exscan leaves rank 0's undefined
      return {first, Utilities::MPI::sum(rows, comm)};
    }

    /// A dataset's name: the field's, spaces as '_' (XDMF's path syntax).
    std::string
    dataset_name(std::string name)
    {
      for (char &c : name)
        if (c == ' ')
          c = '_';
      return name;
    }

    std::string
    data_item(const std::uint64_t rows, const unsigned int columns, const char *type, const unsigned int precision,
              const std::string &path)
    {
      return "<DataItem Dimensions=\"" + std::to_string(rows) + " " + std::to_string(columns) + "\" NumberType=\"" +
             type + "\" Precision=\"" + std::to_string(precision) + "\" Format=\"HDF\">" + path + "</DataItem>";
    }

    /// Writes @p values (n_cells x components, double) as T.
    template <typename T>
    void
    write_field(const hid_t file, const std::string &name, const std::uint64_t total, const unsigned int columns,
                const std::uint64_t first, const std::vector<double> &values)
    {
      if constexpr (std::is_same_v<T, double>)
        write_rows(file, name, total, columns, first, values);
      else
        write_rows(file, name, total, columns, first, std::vector<T>(values.begin(), values.end()));
    }
  } // namespace

  void
  OutputWriter::write_hdf5(const DoFHandler<3>            &dof_handler,
                           const std::vector<bool>        &written_cells,
                           const std::vector<CellField>   &cell_fields,
                           const std::vector<VectorField> &vector_fields,
                           const unsigned int              step,
                           const double                    time,
                           const MPI_Comm                  comm)
  {
    static constexpr unsigned int vtk_order[8] = {0, 1, 3, 2, 4, 5, 7, 6}; // deal.II's to VTK's
    const auto cells = written_hexahedra(dof_handler, written_cells, "Output/Field format = hdf5");
    std::vector<unsigned int> indices;
    for (const auto &cell : cells)
      indices.push_back(cell->active_cell_index());
    const auto [first_cell, total_cells] = rows_of_rank(cells.size(), comm);
    const std::string stem               = base_name + "_" + Utilities::int_to_string(step, 6);
    const char       *real               = "Float";
    const unsigned int precision         = double_precision ? 8 : 4;

    // The mesh, when a rank's written cells differ from the last mesh's.
    if (Utilities::MPI::logical_or(indices != mesh_cells || mesh_file.empty(), comm))
      {
        std::vector<unsigned int> node_of_vertex(dof_handler.get_triangulation().n_vertices(),
                                                 numbers::invalid_unsigned_int);
        std::vector<double>        nodes;
        std::vector<std::uint32_t> connectivity;
        connectivity.reserve(8 * cells.size());
        for (const auto &cell : cells)
          for (const unsigned int v : vtk_order)
            {
              unsigned int &node = node_of_vertex[cell->vertex_index(v)];
              if (node == numbers::invalid_unsigned_int)
                {
                  node = nodes.size() / 3;
                  for (unsigned int d = 0; d < 3; ++d)
                    nodes.push_back(cell->vertex(v)[d]);
                }
              connectivity.push_back(node);
            }
        const auto [first_node, total_nodes] = rows_of_rank(nodes.size() / 3, comm);
        AssertThrow(total_nodes < std::uint64_t(1) << 32,
                    ExcMessage("Output/Field format = hdf5: more than 2^32 mesh nodes"));
        for (auto &node : connectivity)
          node += first_node;
        mesh_file = stem + ".mesh.h5";
        SharedFile file(directory, mesh_file, comm);
        if (double_precision)
          write_field<double>(file, "nodes", total_nodes, 3, first_node, nodes);
        else
          write_field<float>(file, "nodes", total_nodes, 3, first_node, nodes);
        write_rows(file, "cells", total_cells, 8, first_cell, connectivity);
        file.finish();
        mesh_cells       = indices;
        mesh_cells_total = total_cells;
        mesh_nodes_total = total_nodes;
      }

    std::ostringstream grid;
    grid << std::setprecision(17) << "<Grid Name=\"" << stem << "\" GridType=\"Uniform\">\n  <Time Value=\"" << time
         << "\"/>\n  <Topology TopologyType=\"Hexahedron\" NumberOfElements=\"" << total_cells << "\">\n    "
         << data_item(total_cells, 8, "UInt", 4, mesh_file + ":/cells")
         << "\n  </Topology>\n  <Geometry GeometryType=\"XYZ\">\n    "
         << data_item(mesh_nodes_total, 3, real, precision, mesh_file + ":/nodes") << "\n  </Geometry>\n";
    // A 3x3 tensor is declared a Scalar of 9 components: ParaView's XDMF
    // Reader transposes a Tensor (and a Matrix) into VTK's column-major
    // order, so its components would not be the VTU files' (row-major).
    const auto attribute = [&](const std::string &name, const unsigned int columns) {
      grid << "  <Attribute Name=\"" << name << "\" AttributeType=\""
           << (columns == 3 ? "Vector" : "Scalar") << "\" Center=\"Cell\">\n    "
           << data_item(total_cells, columns, real, precision, stem + ".h5:/" + dataset_name(name))
           << "\n  </Attribute>\n";
    };

    SharedFile          file(directory, stem + ".h5", comm);
    std::vector<double> values;
    const auto          write = [&](const std::string &name, const unsigned int columns) {
      if (double_precision)
        write_field<double>(file, dataset_name(name), total_cells, columns, first_cell, values);
      else
        write_field<float>(file, dataset_name(name), total_cells, columns, first_cell, values);
      attribute(name, columns);
    };
    // A nodal vector at the cell's centre: its DoFs times the shape
    // functions there (a DG0 cell's one value; an FE cell's interpolant, the
    // mean of its vertex values for Q1).
    std::map<unsigned int, std::vector<std::pair<unsigned int, double>>> centre_weights; // by active FE index
    const auto weights = [&](const DoFHandler<3>::active_cell_iterator &cell) -> const auto & {
      auto [it, fresh] = centre_weights.try_emplace(cell->active_fe_index());
      if (fresh)
        {
          const FiniteElement<3> &fe = cell->get_fe();
          for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
            {
              const unsigned int d = fe.system_to_component_index(i).first;
              it->second.emplace_back(d, fe.shape_value_component(i, Point<3>(0.5, 0.5, 0.5), d));
            }
        }
      return it->second;
    };
    std::vector<types::global_dof_index> dofs;
    for (const auto &[name, vector] : vector_fields)
      {
        values.assign(3 * cells.size(), 0.0);
        for (std::size_t c = 0; c < cells.size(); ++c)
          {
            const auto &w = weights(cells[c]);
            dofs.resize(w.size());
            cells[c]->get_dof_indices(dofs);
            for (unsigned int i = 0; i < w.size(); ++i)
              values[3 * c + w[i].first] += w[i].second * (*vector)(dofs[i]);
          }
        write(name, 3);
      }
    for (const auto &f : cell_fields)
      {
        const unsigned int n = f.components.size();
        values.resize(n * cells.size());
        for (std::size_t c = 0; c < cells.size(); ++c)
          for (unsigned int k = 0; k < n; ++k)
            values[n * c + k] = (*f.components[k])[indices[c]];
        write(f.name, n);
      }
    file.finish();

    grid << "</Grid>\n";
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      {
        xdmf_grids.push_back(grid.str());
        std::string text = "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n<Xdmf Version=\"2.0\">\n"
                           "<Domain>\n<Grid Name=\"" +
                           base_name + "\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
        for (const auto &g : xdmf_grids)
          text += g;
        text += "</Grid>\n</Domain>\n</Xdmf>\n";
        write_file_atomically(directory + "/" + base_name + ".xdmf", text);
      }
  }
} // namespace perideal
