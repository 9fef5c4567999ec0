// Output/Field format = exodus: Peridigm's output, an Exodus II file. Each PD
// point is a node with a SPHERE element in its block's element block, at its
// reference position, as Peridigm writes them; each continuum cell is a HEX8
// on its vertices. The vector fields (Displacement, Velocity, Force, ...) are
// nodal variables with X, Y and Z appended to their names (DisplacementX);
// the cell fields are element variables (Damage; a vector's components X, Y,
// Z; a tensor's XX, XY, ... row-major), spaces in names as '_'; the columns
// of the globals row are global variables. The file grows by one time step
// per output step.
//
// Exodus files = joined: one <base name>.e for all ranks. Rank 0 defines it,
// then each rank in turn opens it and writes its own nodes and elements
// (their ranges follow the ranks' order), so no rank holds more than its own
// part. per rank: each rank writes <base name>.e.N.r with its own points, as
// Peridigm does in parallel; ParaView opens the pieces as one.

#include <perideal/output/output.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/utilities.h>
#include <deal.II/fe/fe.h>

#include <exodusII.h>

#include <cctype>
#include <functional>
#include <map>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    /// A failed Exodus call; on_ranks() makes every rank stop with it.
    struct ExodusError
    {
      std::string message;
    };

    /// An Exodus file open for writing, closed when it goes out of scope.
    class ExodusWriteFile
    {
    public:
      ExodusWriteFile(const std::string &file, const bool create, const bool double_precision)
        : file(file)
      {
        ex_opts(0); // no messages of its own, no abort: check() says what went wrong
        int cpu_word = sizeof(double), io_word = double_precision ? 8 : 4;
        if (create)
          id = ex_create(file.c_str(), EX_CLOBBER | EX_LARGE_MODEL | EX_ALL_INT64_API, &cpu_word, &io_word);
        else
          {
            float version = 0;
            id            = ex_open(file.c_str(), EX_WRITE | EX_ALL_INT64_API, &cpu_word, &io_word, &version);
          }
        if (id < 0)
          throw ExodusError{"Output/Field format = exodus: cannot " + std::string(create ? "create" : "open") +
                            " the file '" + file + "'"};
        ex_set_max_name_length(id, max_name_length);
      }
      ~ExodusWriteFile()
      {
        if (id >= 0)
          ex_close(id);
      }
      ExodusWriteFile(const ExodusWriteFile &) = delete;
      ExodusWriteFile &
      operator=(const ExodusWriteFile &) = delete;

      void
      check(const int status, const std::string &what) const
      {
        if (status < 0)
          throw ExodusError{"Output/Field format = exodus: cannot write " + what + " to '" + file + "'"};
      }
      /// Closes the file, so that the next rank may open it.
      void
      close()
      {
        const int status = ex_close(id);
        id               = -1;
        check(status, "the last data");
      }

      static constexpr int max_name_length = 80;
      int                  id              = -1;
      std::string          file;
    };

    /// Runs @p write on every rank: each in turn, rank 0 first, if
    /// @p in_turn (they write one file), else all at once; an error on one
    /// rank stops every rank with its message. Collective.
    void
    on_ranks(const MPI_Comm comm, const bool in_turn, const std::function<void()> &write)
    {
      const unsigned int rank = Utilities::MPI::this_mpi_process(comm);
      const unsigned int n    = Utilities::MPI::n_mpi_processes(comm);
      constexpr int      tag  = 4711;
      int                ok   = 1;
      if (in_turn && rank > 0)
        MPI_Recv(&ok, 1, MPI_INT, rank - 1, tag, comm, MPI_STATUS_IGNORE);
      std::string problem;
      if (ok)
        try
          {
            write();
          }
        catch (const ExodusError &e)
          {
            problem = e.message;
            ok      = 0;
          }
      if (in_turn && rank + 1 < n)
        MPI_Send(&ok, 1, MPI_INT, rank + 1, tag, comm);
      if (Utilities::MPI::logical_or(!problem.empty(), comm))
        for (const std::string &p : Utilities::MPI::all_gather(comm, problem))
          AssertThrow(p.empty(), ExcMessage(p));
    }

    /// The variables of a field of @p n components, named as Peridigm names
    /// them: each word capitalised, joined by '_' (Force density:
    /// Force_Density; Block: Block_Id, Rank: Proc_Num), then X, Y, Z for a
    /// vector's components, XX, XY, ... for a tensor's (row-major).
    std::vector<std::string>
    variable_names(const std::string &field, const unsigned int n)
    {
      std::string base = field == "Block" ? "Block_Id" : field == "Rank" ? "Proc_Num" : field;
      for (std::size_t k = 0; k < base.size(); ++k)
        if (base[k] == ' ')
          base[k] = '_';
        else if (k == 0 || base[k - 1] == '_')
          base[k] = std::toupper(static_cast<unsigned char>(base[k]));
      static const char *const xyz = "XYZ";
      std::vector<std::string> names;
      if (n == 1)
        names.push_back(base);
      else if (n == 3)
        for (unsigned int d = 0; d < 3; ++d)
          names.push_back(base + xyz[d]);
      else if (n == 9)
        for (unsigned int a = 0; a < 3; ++a)
          for (unsigned int b = 0; b < 3; ++b)
            names.push_back(base + xyz[a] + xyz[b]);
      else
        for (unsigned int c = 0; c < n; ++c)
          names.push_back(base + "_" + std::to_string(c));
      return names;
    }

    /// ex_put_names()'s and ex_put_variable_names()' char *[].
    std::vector<char *>
    c_strings(std::vector<std::string> &names)
    {
      std::vector<char *> pointers;
      for (auto &name : names)
        pointers.push_back(name.data());
      return pointers;
    }

    /// This rank's nodes and elements: the points' nodes, then the
    /// continuum cells' vertices (each once per rank); the elements block by
    /// block, each with its cell (whose DoFs and cell field entries hold its
    /// values).
    struct LocalMesh
    {
      std::vector<double>                                            x, y, z;
      std::vector<std::int64_t>                                      node_id;
      std::vector<std::pair<DoFHandler<3>::active_cell_iterator, unsigned int>> node_source; // (cell, vertex or 0)
      std::vector<std::vector<DoFHandler<3>::active_cell_iterator>> element_cells;           // by block
      std::vector<std::vector<std::int64_t>>                         connectivity;            // by block, local nodes from 0
      std::vector<std::vector<std::int64_t>>                         element_id;              // by block
      std::vector<unsigned int>                                      signature; // (block, active cell index) of each element
    };

    LocalMesh
    local_mesh(const OutputWriter::ExodusMesh &mesh, const MPI_Comm comm)
    {
      // A vertex on the boundary between two ranks' cells is a node of each:
      // its ids differ by rank.
      const std::int64_t rank    = Utilities::MPI::this_mpi_process(comm);
      const std::int64_t n_ranks = Utilities::MPI::n_mpi_processes(comm);
      // deal.II's vertex order to Exodus' HEX8 (VTK's hexahedron's).
      static constexpr unsigned int hex8_order[8] = {0, 1, 3, 2, 4, 5, 7, 6};
      const unsigned int            n_blocks      = mesh.blocks.size();
      LocalMesh                     local;
      local.element_cells.resize(n_blocks);
      local.connectivity.resize(n_blocks);
      local.element_id.resize(n_blocks);
      for (std::size_t k = 0; k < mesh.point_cells.size(); ++k)
        {
          const unsigned int node = local.x.size();
          local.x.push_back(mesh.point_X[3 * k]);
          local.y.push_back(mesh.point_X[3 * k + 1]);
          local.z.push_back(mesh.point_X[3 * k + 2]);
          local.node_id.push_back(mesh.point_id[k]);
          local.node_source.emplace_back(mesh.point_cells[k], 0);
          const unsigned int b = mesh.point_block[k];
          local.element_cells[b].push_back(mesh.point_cells[k]);
          local.connectivity[b].push_back(node);
          local.element_id[b].push_back(mesh.point_id[k]);
          local.signature.insert(local.signature.end(), {b, mesh.point_cells[k]->active_cell_index()});
        }
      std::map<unsigned int, unsigned int> node_of_vertex;
      for (std::size_t k = 0; k < mesh.fe_cells.size(); ++k)
        {
          const auto        &cell = mesh.fe_cells[k];
          const unsigned int b    = mesh.fe_block[k];
          for (const unsigned int v : hex8_order)
            {
              const auto [it, fresh] = node_of_vertex.try_emplace(cell->vertex_index(v), local.x.size());
              if (fresh)
                {
                  local.x.push_back(cell->vertex(v)[0]);
                  local.y.push_back(cell->vertex(v)[1]);
                  local.z.push_back(cell->vertex(v)[2]);
                  local.node_id.push_back(mesh.point_ids_end + n_ranks * cell->vertex_index(v) + rank + 1);
                  local.node_source.emplace_back(cell, v);
                }
              local.connectivity[b].push_back(it->second);
            }
          local.element_cells[b].push_back(cell);
          local.element_id[b].push_back(mesh.point_ids_end + cell->global_active_cell_index() + 1);
          local.signature.insert(local.signature.end(), {b, cell->active_cell_index()});
        }
      return local;
    }

    /// Where this rank's part goes in the file: its first node and its first
    /// element in each block (from 0), and the totals.
    struct Ranges
    {
      std::uint64_t              first_node = 0, n_nodes = 0, n_elements = 0;
      std::vector<std::uint64_t> first_in_block, in_block, block_start;
    };

    Ranges
    ranges(const LocalMesh &local, const bool joined, const MPI_Comm comm)
    {
      const unsigned int         n_blocks = local.element_cells.size();
      std::vector<std::uint64_t> counts(n_blocks + 1);
      counts[0] = local.x.size();
      for (unsigned int b = 0; b < n_blocks; ++b)
        counts[b + 1] = local.element_cells[b].size();
      std::vector<std::uint64_t> first(n_blocks + 1, 0), total = counts;
      if (joined)
        {
          MPI_Exscan(counts.data(), first.data(), n_blocks + 1, MPI_UINT64_T, MPI_SUM, comm);
          if (Utilities::MPI::this_mpi_process(comm) == 0)
            std::fill(first.begin(), first.end(), 0); // MPI_Exscan leaves rank 0's undefined
          MPI_Allreduce(counts.data(), total.data(), n_blocks + 1, MPI_UINT64_T, MPI_SUM, comm);
        }
      Ranges r;
      r.first_node = first[0];
      r.n_nodes    = total[0];
      r.first_in_block.assign(first.begin() + 1, first.end());
      r.in_block.assign(total.begin() + 1, total.end());
      for (unsigned int b = 0; b < n_blocks; ++b)
        {
          r.block_start.push_back(r.n_elements);
          r.n_elements += r.in_block[b];
        }
      return r;
    }
  } // namespace

  std::string
  OutputWriter::exodus_file_name(const MPI_Comm comm) const
  {
    std::string name = directory + "/" + base_name + ".e";
    if (exodus_files > 1)
      name += "-s" + Utilities::int_to_string(exodus_files, 4);
    if (exodus_per_rank)
      {
        // SEACAS' names of a decomposed file: .N.r, r padded to N's digits.
        const unsigned int n = Utilities::MPI::n_mpi_processes(comm);
        name += "." + std::to_string(n) + "." +
                Utilities::int_to_string(Utilities::MPI::this_mpi_process(comm), std::to_string(n).size());
      }
    return name;
  }

  void
  OutputWriter::write_exodus(const ExodusMesh               &mesh,
                             const std::vector<CellField>   &cell_fields,
                             const std::vector<VectorField> &vector_fields,
                             const GlobalsRow               &globals,
                             const double                    time,
                             const MPI_Comm                  comm)
  {
    const LocalMesh local  = local_mesh(mesh, comm);
    const bool      joined = !exodus_per_rank;
    const Ranges    range  = ranges(local, joined, comm);
    const unsigned int n_blocks = mesh.blocks.size();

    // The variables.
    std::vector<std::string> nodal_names, element_names, global_names;
    for (const auto &[name, vector] : vector_fields)
      for (const auto &v : variable_names(name, 3))
        nodal_names.push_back(v);
    for (const auto &f : cell_fields)
      for (const auto &v : variable_names(f.name, f.components.size()))
        element_names.push_back(v);
    std::vector<double> global_values;
    for (const auto &[name, value] : globals)
      if (name != "step" && name != "time")
        {
          global_names.push_back(name);
          global_values.push_back(value);
        }

    // A new file at the first output step and when the written mesh changes
    // (a conversion or rebalance of Adaptivity): <base name>.e-s0002, ...,
    // each a mesh of its own, as SEACAS names a series whose mesh changes.
    const bool new_file =
      exodus_files == 0 || Utilities::MPI::logical_or(local.signature != exodus_cells, comm);
    if (new_file)
      {
        ++exodus_files;
        exodus_steps   = 0;
        exodus_cells   = local.signature;
        exodus_globals = global_names;
      }
    const std::string file = exodus_file_name(comm);
    const int         step = ++exodus_steps;
    const bool        writes_globals = !global_names.empty() && global_names == exodus_globals;
    const bool        first_rank     = !joined || Utilities::MPI::this_mpi_process(comm) == 0;

    // Defines the file: its sizes, blocks, names and variables.
    const auto define = [&]() {
      ExodusWriteFile out(file, true, double_precision);
      const std::string title = ("PeriDeal " + base_name).substr(0, 80);
      out.check(ex_put_init(out.id, title.c_str(), 3, range.n_nodes, range.n_elements, n_blocks, 0, 0),
                "the sizes");
      if (!joined)
        {
          char kind[] = "p";
          out.check(ex_put_init_info(out.id, Utilities::MPI::n_mpi_processes(comm), 1, kind),
                    "the decomposition");
        }
      std::vector<std::string> block_names;
      for (unsigned int b = 0; b < n_blocks; ++b)
        {
          const bool continuum = mesh.blocks[b].continuum;
          out.check(ex_put_block(out.id, EX_ELEM_BLOCK, mesh.blocks[b].id, continuum ? "HEX8" : "SPHERE",
                                 range.in_block[b], continuum ? 8 : 1, 0, 0, 0),
                    "the block '" + mesh.blocks[b].name + "'");
          block_names.push_back(mesh.blocks[b].name.substr(0, ExodusWriteFile::max_name_length));
        }
      if (n_blocks > 0)
        out.check(ex_put_names(out.id, EX_ELEM_BLOCK, c_strings(block_names).data()), "the block names");
      std::vector<std::string> coordinates{"x", "y", "z"};
      out.check(ex_put_coord_names(out.id, c_strings(coordinates).data()), "the coordinate names");
      const auto variables = [&](const ex_entity_type type, std::vector<std::string> names) {
        if (names.empty())
          return;
        out.check(ex_put_variable_param(out.id, type, names.size()), "the variables");
        out.check(ex_put_variable_names(out.id, type, names.size(), c_strings(names).data()), "the variable names");
      };
      variables(EX_NODAL, nodal_names);
      variables(EX_ELEM_BLOCK, element_names);
      variables(EX_GLOBAL, exodus_globals);
      if (!element_names.empty() && n_blocks > 0)
        {
          std::vector<int> truth(n_blocks * element_names.size(), 1);
          out.check(ex_put_truth_table(out.id, EX_ELEM_BLOCK, n_blocks, element_names.size(), truth.data()),
                    "the truth table");
        }
      out.close();
    };

    // This rank's part: the mesh in a new file, then the step's values.
    const auto write_part = [&]() {
      ExodusWriteFile out(file, false, double_precision);
      const std::int64_t n_local = local.x.size();
      if (new_file)
        {
          if (n_local > 0)
            {
              out.check(ex_put_partial_coord(out.id, range.first_node + 1, n_local, local.x.data(), local.y.data(),
                                             local.z.data()),
                        "the coordinates");
              out.check(ex_put_partial_node_num_map(out.id, range.first_node + 1, n_local, local.node_id.data()),
                        "the node ids");
            }
          for (unsigned int b = 0; b < n_blocks; ++b)
            if (const std::int64_t n = local.element_cells[b].size(); n > 0)
              {
                std::vector<std::int64_t> connectivity = local.connectivity[b];
                for (auto &node : connectivity)
                  node += range.first_node + 1;
                out.check(ex_put_partial_elem_conn(out.id, mesh.blocks[b].id, range.first_in_block[b] + 1, n,
                                                   connectivity.data()),
                          "the connectivity of block '" + mesh.blocks[b].name + "'");
                out.check(ex_put_partial_elem_num_map(out.id, range.block_start[b] + range.first_in_block[b] + 1, n,
                                                      local.element_id[b].data()),
                          "the element ids");
              }
        }
      if (first_rank)
        {
          out.check(ex_put_time(out.id, step, &time), "the time");
          if (writes_globals)
            out.check(ex_put_var(out.id, step, EX_GLOBAL, 1, 0, global_values.size(), global_values.data()),
                      "the global variables");
        }
      // Each node's DoF of each component, once for every vector field: a
      // point's is its cell's one DoF per component, a continuum vertex's
      // the vertex's (FE_Q numbers its vertex DoFs first).
      std::vector<types::global_dof_index> node_dofs, dofs;
      if (!vector_fields.empty())
        for (const auto &[cell, v] : local.node_source)
          {
            const FiniteElement<3> &fe = cell->get_fe();
            dofs.resize(fe.n_dofs_per_cell());
            cell->get_dof_indices(dofs);
            for (unsigned int d = 0; d < 3; ++d)
              node_dofs.push_back(dofs.empty() ? numbers::invalid_dof_index :
                                                 dofs[fe.component_to_system_index(d, fe.degree == 0 ? 0 : v)]);
          }
      std::vector<double> values;
      int                 index = 0;
      for (const auto &[name, vector] : vector_fields)
        for (unsigned int d = 0; d < 3; ++d)
          {
            ++index;
            values.clear();
            for (std::int64_t n = 0; n < n_local; ++n)
              {
                const types::global_dof_index dof = node_dofs[3 * n + d];
                values.push_back(dof == numbers::invalid_dof_index ? 0.0 : (*vector)(dof));
              }
            if (n_local > 0)
              out.check(ex_put_partial_var(out.id, step, EX_NODAL, index, 1, range.first_node + 1, n_local, values.data()),
                        "the variable '" + nodal_names[index - 1] + "'");
          }
      index = 0;
      for (const auto &f : cell_fields)
        for (const auto *component : f.components)
          {
            ++index;
            for (unsigned int b = 0; b < n_blocks; ++b)
              if (const std::int64_t n = local.element_cells[b].size(); n > 0)
                {
                  values.clear();
                  for (const auto &cell : local.element_cells[b])
                    values.push_back((*component)[cell->active_cell_index()]);
                  out.check(ex_put_partial_var(out.id, step, EX_ELEM_BLOCK, index, mesh.blocks[b].id,
                                               range.first_in_block[b] + 1, n, values.data()),
                            "the variable '" + element_names[index - 1] + "'");
                }
          }
      out.close();
    };

    if (new_file)
      on_ranks(comm, false, [&]() {
        if (first_rank)
          define();
      });
    on_ranks(comm, joined, write_part);
  }
} // namespace perideal
