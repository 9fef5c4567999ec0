// Region Type = Node set, Side set, Element block: the cells of a set that
// the mesh file names (an Exodus mesh's, SceneGeometry::mesh_sets()), chosen
// by its name; Point numbers: the points a Peridigm deck's own node set
// lists by number.
#include <perideal/geometry/region.h>

#include <deal.II/grid/tria.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    enum class SetKind
    {
      node_set,
      side_set,
      element_block
    };

    /// Whether @p cell descends from one of @p cells (sorted level-0 indices):
    /// deal.II 9.4 keeps the map from coarse cell ids to indices private.
    bool
    contains_cell(const std::vector<unsigned int> &cells, const DoFHandler<dim>::active_cell_iterator &cell)
    {
      typename Triangulation<dim>::cell_iterator ancestor = cell;
      while (ancestor->level() > 0)
        ancestor = ancestor->parent();
      return std::binary_search(cells.begin(), cells.end(), static_cast<unsigned int>(ancestor->index()));
    }

    template <SetKind kind>
    class MeshSetRegion : public RegionSelector
    {
    public:
      static constexpr const char *key = kind == SetKind::node_set ? "Node set" :
                                         kind == SetKind::side_set ? "Side set" :
                                                                     "Element block";

      static void
      declare_parameters(ParameterHandler &prm)
      {
        const std::string doc =
          kind == SetKind::node_set ?
            "Node set: the name of a node set of the mesh file, or nodelist_<id> (Peridigm's name of a node set "
            "the file does not name). With sphere elements a point is in it if its node is; otherwise a point "
            "or cell is in it if one of its element's nodes is, as Peridigm converts node sets." :
          kind == SetKind::side_set ?
            "Side set: the name of a side set of the mesh file, or surfacelist_<id>: the points or cells of the "
            "elements with a side in it." :
            "Element block: the name of an element block of the mesh file, or block_<id> (Peridigm's name of a "
            "block the file does not name): its points or cells.";
        prm.declare_entry(key, "", Patterns::Anything(), doc);
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path, const SceneGeometry &geometry) override
      {
        const std::string name = prm.get(key);
        const auto       *sets = geometry.mesh_sets();
        AssertThrow(sets != nullptr,
                    ExcMessage(path + "/Type = " + key + ": the scene's mesh names no sets (" + key +
                               "s come with Discretization/Type = Exodus)"));
        const auto &named = kind == SetKind::node_set ? sets->node_sets :
                            kind == SetKind::side_set ? sets->side_sets :
                                                        sets->element_blocks;
        const auto  it    = named.find(name);
        if (it == named.end())
          {
            std::string known;
            for (const auto &entry : named)
              known += (known.empty() ? "'" : ", '") + entry.first + "'";
            AssertThrow(false, ExcMessage(path + "/" + key + ": the mesh has no " + std::string(key) + " '" + name +
                                          "'; it has " + (known.empty() ? std::string("none") : known)));
          }
        cells = it->second;
      }

      bool
      contains(const Point<dim> &, const DoFHandler<dim>::active_cell_iterator &cell) const override
      {
        return contains_cell(cells, cell);
      }

    private:
      std::vector<unsigned int> cells; // sorted level-0 indices
    };

    class PointNumbersRegion : public RegionSelector
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Point numbers", "", Patterns::Anything(),
                          "Point numbers: the numbers (from 1, separated by spaces or commas) of the points, as a "
                          "Peridigm deck's own node sets give them: the elements of an Exodus mesh (their ids, "
                          "the element map), the points of a Text file in the order of its lines, the cells of a "
                          "Box in PdQuickGrid's order (x fastest, then y, then z).");
        prm.declare_entry("Point number file", "", Patterns::Anything(),
                          "Point numbers: a file of such numbers instead (Peridigm's node set file: numbers "
                          "separated by white space; lines beginning with #, / or * are comments). A relative "
                          "path is taken from the directory the run starts in.");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &path, const SceneGeometry &geometry) override
      {
        const std::string list = prm.get("Point numbers"), file = prm.get("Point number file");
        AssertThrow(list.empty() != file.empty(),
                    ExcMessage(path + "/Type = Point numbers: give either Point numbers or Point number file"));
        const auto *sets     = geometry.mesh_sets();
        const bool  by_cells = sets != nullptr && !sets->point_cells.empty();
        AssertThrow(by_cells || geometry.n_numbered_points() > 0,
                    ExcMessage(path + "/Type = Point numbers: the scene's points have no numbers (they come "
                                      "with Discretization/Type = Exodus, Text file and Box)"));
        if (!by_cells)
          scene = &geometry;
        const std::string where = file.empty() ? path + "/Point numbers" : path + "/Point number file '" + file + "'";
        std::string text = list;
        if (!file.empty())
          text = read_numbers_file(file, path);
        std::replace(text.begin(), text.end(), ',', ' ');
        std::istringstream in(text);
        for (std::string word; in >> word;)
          {
            std::size_t end = 0;
            long        n   = 0;
            try
              {
                n = std::stol(word, &end);
              }
            catch (const std::exception &)
              {
                end = 0;
              }
            AssertThrow(end == word.size() && end > 0,
                        ExcMessage(where + ": '" + word + "' is not a point number (a whole number from 1)"));
            if (!by_cells)
              {
                AssertThrow(n >= 1 && n <= geometry.n_numbered_points(),
                            ExcMessage(where + ": there is no point " + word + " (the points are numbered from 1 to " +
                                       std::to_string(geometry.n_numbered_points()) + ")"));
                numbers.push_back(n);
                continue;
              }
            const auto &numbered = sets->point_cells;
            const auto  it       = std::lower_bound(numbered.begin(), numbered.end(), std::make_pair(n, 0u));
            AssertThrow(it != numbered.end() && it->first == n,
                        ExcMessage(where + ": there is no point " + word + " (the points are numbered from " +
                                   std::to_string(numbered.front().first) + " to " +
                                   std::to_string(numbered.back().first) + ")"));
            cells.push_back(it->second);
          }
        std::sort(cells.begin(), cells.end());
        cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
        std::sort(numbers.begin(), numbers.end());
      }

      bool
      contains(const Point<dim> &, const DoFHandler<dim>::active_cell_iterator &cell) const override
      {
        if (scene != nullptr)
          return std::binary_search(numbers.begin(), numbers.end(), scene->point_number(cell->center()));
        return contains_cell(cells, cell);
      }

    private:
      /// The numbers of a node set file, comment lines left out.
      static std::string
      read_numbers_file(const std::string &file, const std::string &path)
      {
        const std::string key = path + "/Point number file";
        std::error_code   error;
        AssertThrow(std::filesystem::is_regular_file(std::filesystem::status(file, error)),
                    ExcMessage(key + ": '" + file + "' " +
                               (std::filesystem::exists(std::filesystem::status(file, error)) ?
                                  "is not a regular file" :
                                  "does not exist")));
        std::ifstream in(file);
        AssertThrow(in, ExcMessage(key + ": cannot open '" + file + "'"));
        std::string text, line;
        while (std::getline(in, line))
          {
            const auto first = line.find_first_not_of(" \t\r");
            if (first != std::string::npos && line[first] != '#' && line[first] != '/' && line[first] != '*')
              text += line + ' ';
          }
        return text;
      }

      std::vector<unsigned int> cells;           // sorted level-0 indices, or
      std::vector<long>         numbers;         // the sorted numbers, of
      const SceneGeometry      *scene = nullptr; // a scene that numbers its points by position
    };

    using NodeSetRegion      = MeshSetRegion<SetKind::node_set>;
    using SideSetRegion      = MeshSetRegion<SetKind::side_set>;
    using ElementBlockRegion = MeshSetRegion<SetKind::element_block>;
  } // namespace

  PERIDEAL_REGISTER(RegionSelector, NodeSetRegion, "Node set",
                    "the points of a node set of the mesh file (Discretization/Type = Exodus), by name.")
  PERIDEAL_REGISTER(RegionSelector, SideSetRegion, "Side set",
                    "the points of the elements with a side in a side set of the mesh file, by name.")
  PERIDEAL_REGISTER(RegionSelector, PointNumbersRegion, "Point numbers",
                    "the points a Peridigm deck's own node set lists by number (Exodus, Text file, Box).")
  PERIDEAL_REGISTER(RegionSelector, ElementBlockRegion, "Element block",
                    "the points of an element block of the mesh file, by name.")
} // namespace perideal
