// An Exodus II mesh file read through the Exodus II library (exodus_file.h).

#include <perideal/geometry/exodus_file.h>

#include <deal.II/base/exceptions.h>

#include <exodusII.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>
#include <regex>
#include <set>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    /// One open file, closed when it goes out of scope (also when a check
    /// throws).
    class ExodusFile
    {
    public:
      ExodusFile(const std::string &file, const std::string &where)
        : where(where)
      {
        ex_opts(0); // no messages of its own, no abort: the checks below say what went wrong
        int   cpu_word = sizeof(double), io_word = 0;
        float version = 0;
        id            = ex_open(file.c_str(), EX_READ, &cpu_word, &io_word, &version);
        AssertThrow(id >= 0,
                    ExcMessage(where + " cannot be opened as an Exodus II file (not a netCDF file, or not "
                                       "readable): give a .g or .e mesh written by Cubit, SEACAS or Peridigm's "
                                       "tools"));
        // Names as long as the file holds them (32 characters by default).
        const int longest = static_cast<int>(ex_inquire_int(id, EX_INQ_DB_MAX_USED_NAME_LENGTH));
        name_length       = std::max(longest, 32);
        ex_set_max_name_length(id, name_length);
      }

      ~ExodusFile()
      {
        ex_close(id);
      }

      ExodusFile(const ExodusFile &) = delete;
      ExodusFile &
      operator=(const ExodusFile &) = delete;

      /// Refuses the file if an Exodus call failed: it lacks @p what or is
      /// cut short.
      void
      check(const int status, const std::string &what) const
      {
        AssertThrow(status >= 0,
                    ExcMessage(where + ": cannot read " + what +
                                 " (the file is truncated or not a complete Exodus II mesh)"));
      }

      std::string
      name(const ex_entity_type type, const long entity_id, const std::string &otherwise) const
      {
        std::vector<char> text(name_length + 1, '\0');
        check(ex_get_name(id, type, entity_id, text.data()), "the name of " + otherwise);
        std::string n(text.data());
        n.erase(n.find_last_not_of(' ') + 1);
        return n.empty() ? otherwise : n;
      }

      int         id = -1;
      std::string where;

    private:
      int name_length = 32;
    };

    struct Counts
    {
      int dimension = 0, nodes = 0, elements = 0, blocks = 0, node_sets = 0, side_sets = 0;
    };

    std::vector<int>
    id_map(const ExodusFile &f, const ex_entity_type type, const int n, const std::string &what)
    {
      std::vector<int> map(n);
      if (n > 0)
        f.check(ex_get_id_map(f.id, type, map.data()), "its " + what + " number map");
      return map;
    }

    /// Adds the piece @p file to @p mesh; a side set's elements are given by
    /// their global numbers, a node set's nodes by their indices in mesh.nodes.
    void
    read_piece(const std::string &file, const std::string &where, const bool decomposed, ExodusMesh &mesh)
    {
      const ExodusFile f(file, where);
      Counts           n;
      char             title[MAX_LINE_LENGTH + 1] = {};
      f.check(ex_get_init(f.id, title, &n.dimension, &n.nodes, &n.elements, &n.blocks, &n.node_sets, &n.side_sets),
              "its sizes (ex_get_init)");
      AssertThrow(n.dimension == 3,
                  ExcMessage(where + " is a mesh of dimension " + std::to_string(n.dimension) +
                             ": PeriDeal reads 3D Exodus meshes (num_dim = 3)"));
      AssertThrow(n.nodes >= 0 && n.elements >= 0 && n.blocks >= 0 && n.node_sets >= 0 && n.side_sets >= 0,
                  ExcMessage(where + ": its sizes are negative: not an Exodus II mesh"));

      // The nodes, placed by their global numbers.
      std::vector<double> x(n.nodes), y(n.nodes), z(n.nodes);
      if (n.nodes > 0)
        f.check(ex_get_coord(f.id, x.data(), y.data(), z.data()), "its node coordinates");
      // The global numbers of a piece; a whole file's are their places (its
      // maps, which may number from anywhere, name them for other programs).
      const std::vector<int> element_id = id_map(f, EX_ELEM_MAP, n.elements, "element");
      std::vector<int>       node_number(n.nodes), element_number(n.elements);
      std::iota(node_number.begin(), node_number.end(), 1);
      std::iota(element_number.begin(), element_number.end(), 1);
      if (decomposed)
        {
          node_number    = id_map(f, EX_NODE_MAP, n.nodes, "node");
          element_number = element_id;
        }
      for (int i = 0; i < n.nodes; ++i)
        {
          AssertThrow(node_number[i] >= 1,
                      ExcMessage(where + ": node " + std::to_string(i + 1) + " has the global number " +
                                 std::to_string(node_number[i]) + " (they begin at 1)"));
          if (std::size_t(node_number[i]) > mesh.nodes.size())
            mesh.nodes.resize(node_number[i], Point<dim>(NAN, NAN, NAN));
          mesh.nodes[node_number[i] - 1] = Point<dim>(x[i], y[i], z[i]);
        }
      const auto global_node = [&](const long local) {
        AssertThrow(local >= 1 && local <= n.nodes,
                    ExcMessage(where + ": an element or node set names node " + std::to_string(local) +
                               ", and the file has nodes 1 to " + std::to_string(n.nodes) +
                               ": the file is truncated or not a complete Exodus II mesh"));
        return long(node_number[local - 1]) - 1;
      };

      // The element blocks, merged by id with the other pieces'.
      std::vector<int> block_ids(n.blocks);
      if (n.blocks > 0)
        f.check(ex_get_elem_blk_ids(f.id, block_ids.data()), "its element block ids");
      long first_element = 0; // of the block, in the piece's numbering from 0
      for (const int block_id : block_ids)
        {
          const std::string block = "element block " + std::to_string(block_id);
          char              type[MAX_STR_LENGTH + 1] = {};
          int               count = 0, per_element = 0, n_attributes = 0;
          f.check(ex_get_elem_block(f.id, block_id, type, &count, &per_element, &n_attributes), block);
          auto it = std::find_if(mesh.blocks.begin(), mesh.blocks.end(),
                                 [&](const ExodusMesh::Block &b) { return b.id == block_id; });
          if (it == mesh.blocks.end())
            {
              it       = mesh.blocks.insert(mesh.blocks.end(), ExodusMesh::Block());
              it->id   = block_id;
              it->name = f.name(EX_ELEM_BLOCK, block_id, "block_" + std::to_string(block_id));
            }
          std::string upper(type);
          std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return std::toupper(c); });
          if (count > 0)
            {
              AssertThrow(it->numbers.empty() ||
                            (it->type == upper && int(it->nodes_per_element) == per_element &&
                             int(it->n_attributes) == n_attributes),
                          ExcMessage(where + ": " + block + " differs between the pieces of the decomposition"));
              it->type              = upper;
              it->nodes_per_element = per_element;
              it->n_attributes      = n_attributes;
              std::vector<int> connectivity(std::size_t(count) * per_element);
              if (!connectivity.empty())
                f.check(ex_get_elem_conn(f.id, block_id, connectivity.data()), "the connectivity of " + block);
              std::vector<double> attributes(std::size_t(count) * n_attributes);
              if (!attributes.empty())
                f.check(ex_get_elem_attr(f.id, block_id, attributes.data()), "the attributes of " + block);
              for (int e = 0; e < count; ++e)
                {
                  it->numbers.push_back(element_number.at(first_element + e));
                  it->ids.push_back(element_id.at(first_element + e));
                }
              for (const int node : connectivity)
                it->connectivity.push_back(global_node(node));
              it->attributes.insert(it->attributes.end(), attributes.begin(), attributes.end());
            }
          first_element += count;
        }
      AssertThrow(first_element == n.elements,
                  ExcMessage(where + ": its blocks hold " + std::to_string(first_element) + " elements, and it says " +
                             std::to_string(n.elements)));

      // The node sets and side sets, merged by id.
      const auto read_sets = [&](const bool nodes) {
        const int count = nodes ? n.node_sets : n.side_sets;
        std::vector<int> ids(count);
        if (count > 0)
          f.check(nodes ? ex_get_node_set_ids(f.id, ids.data()) : ex_get_side_set_ids(f.id, ids.data()),
                  nodes ? "its node set ids" : "its side set ids");
        auto &sets = nodes ? mesh.node_sets : mesh.side_sets;
        for (const int set_id : ids)
          {
            const std::string what = (nodes ? "node set " : "side set ") + std::to_string(set_id);
            auto it = std::find_if(sets.begin(), sets.end(), [&](const ExodusMesh::Set &s) { return s.id == set_id; });
            if (it == sets.end())
              {
                it       = sets.insert(sets.end(), ExodusMesh::Set());
                it->id   = set_id;
                it->name = f.name(nodes ? EX_NODE_SET : EX_SIDE_SET, set_id,
                                  (nodes ? "nodelist_" : "surfacelist_") + std::to_string(set_id));
              }
            int size = 0, factors = 0;
            f.check(nodes ? ex_get_node_set_param(f.id, set_id, &size, &factors) :
                            ex_get_side_set_param(f.id, set_id, &size, &factors),
                    what);
            std::vector<int> items(size), sides(nodes ? 0 : size);
            if (size > 0)
              f.check(nodes ? ex_get_node_set(f.id, set_id, items.data()) :
                              ex_get_side_set(f.id, set_id, items.data(), sides.data()),
                      "the members of " + what);
            for (int k = 0; k < size; ++k)
              if (nodes)
                it->items.push_back(global_node(items[k]));
              else
                {
                  AssertThrow(items[k] >= 1 && items[k] <= n.elements,
                              ExcMessage(where + ": " + what + " names element " + std::to_string(items[k]) +
                                         ", and the file has " + std::to_string(n.elements) + " elements"));
                  it->items.push_back(element_number[items[k] - 1]);
                  it->sides.push_back(sides[k]);
                }
          }
      };
      read_sets(true);
      read_sets(false);
    }

    /// The pieces FILE.N.i of a decomposition of @p file, if all N are there
    /// (the smallest such N); empty if there are none.
    std::vector<std::string>
    decomposition(const std::string &file)
    {
      namespace fs = std::filesystem;
      const fs::path  path(file);
      const fs::path  folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
      const std::string base = path.filename().string();
      std::map<unsigned long, std::map<unsigned long, std::string>> found; // N -> i -> file
      std::error_code error;
      for (fs::directory_iterator it(folder, error), end; !error && it != end; it.increment(error))
        {
          const std::string name = it->path().filename().string();
          if (name.size() <= base.size() + 1 || name.compare(0, base.size() + 1, base + ".") != 0)
            continue;
          static const std::regex suffix("([0-9]{1,9})\\.([0-9]{1,9})");
          std::smatch             m;
          const std::string       rest = name.substr(base.size() + 1);
          if (std::regex_match(rest, m, suffix))
            found[std::stoul(m[1])][std::stoul(m[2])] = it->path().string();
        }
      for (const auto &[n, pieces] : found)
        if (n > 0 && pieces.size() == n && pieces.rbegin()->first == n - 1)
          {
            std::vector<std::string> files;
            for (const auto &[i, f] : pieces)
              files.push_back(f);
            return files;
          }
      return {};
    }
  } // namespace

  ExodusMesh
  read_exodus_file(const std::string &file, const std::string &key)
  {
    namespace fs = std::filesystem;
    std::error_code error;
    std::vector<std::string> files;
    if (fs::exists(fs::status(file, error)))
      {
        AssertThrow(fs::is_regular_file(fs::status(file, error)),
                    ExcMessage(key + ": '" + file + "' is not a regular file (a directory, a FIFO or a device)"));
        files = {file};
      }
    else
      files = decomposition(file);
    AssertThrow(!files.empty(),
                ExcMessage(key + ": '" + file + "' does not exist, nor do the pieces '" + file +
                           ".N.i' (i = 0, ..., N - 1) of a decomposition of it"));

    ExodusMesh mesh;
    mesh.pieces = files.size();
    for (const std::string &piece : files)
      read_piece(piece, key + " '" + piece + "'", files.size() > 1, mesh);

    const std::string where = key + " '" + file + "'" + (files.size() > 1 ? " (decomposed)" : "");
    for (std::size_t i = 0; i < mesh.nodes.size(); ++i)
      AssertThrow(std::isfinite(mesh.nodes[i].norm_square()),
                  ExcMessage(where + ": node " + std::to_string(i + 1) +
                             (files.size() > 1 ? " is in none of the pieces (the global node numbers have gaps)" :
                                                 " is not a finite point")));
    // Each block's elements in the order of their numbers, which must not
    // repeat: pieces of one decomposition share nodes, never elements.
    std::set<long> numbers;
    for (auto &b : mesh.blocks)
      {
        std::vector<std::size_t> order(b.numbers.size());
        std::iota(order.begin(), order.end(), 0);
        std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return b.numbers[i] < b.numbers[j]; });
        ExodusMesh::Block sorted = b;
        for (std::size_t k = 0; k < order.size(); ++k)
          {
            const std::size_t e = order[k];
            AssertThrow(numbers.insert(b.numbers[e]).second,
                        ExcMessage(where + ": element number " + std::to_string(b.numbers[e]) + " appears twice"));
            sorted.numbers[k] = b.numbers[e];
            sorted.ids[k]     = b.ids[e];
            std::copy_n(b.connectivity.begin() + e * b.nodes_per_element, b.nodes_per_element,
                        sorted.connectivity.begin() + k * b.nodes_per_element);
            std::copy_n(b.attributes.begin() + e * b.n_attributes, b.n_attributes,
                        sorted.attributes.begin() + k * b.n_attributes);
          }
        b = std::move(sorted);
      }
    // Peridigm finds blocks and sets by name: a name must be unique.
    const auto unique_names = [&](const auto &list, const std::string &what) {
      std::set<std::string> names;
      for (const auto &entry : list)
        AssertThrow(names.insert(entry.name).second,
                    ExcMessage(where + ": two " + what + " are named '" + entry.name + "'"));
    };
    unique_names(mesh.blocks, "element blocks");
    unique_names(mesh.node_sets, "node sets");
    unique_names(mesh.side_sets, "side sets");
    // A node in a set once (the pieces of a decomposition share nodes).
    for (auto &s : mesh.node_sets)
      {
        std::sort(s.items.begin(), s.items.end());
        s.items.erase(std::unique(s.items.begin(), s.items.end()), s.items.end());
      }
    return mesh;
  }
} // namespace perideal
