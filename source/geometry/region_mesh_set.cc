// Region Type = Node set, Side set, Element block: the cells of a set that
// the mesh file names (an Exodus mesh's, SceneGeometry::mesh_sets()), chosen
// by its name.
#include <perideal/geometry/region.h>

#include <deal.II/grid/tria.h>

#include <algorithm>

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
        // The coarse cell's index is its level-0 ancestor's (deal.II 9.4
        // keeps the map from coarse cell ids to indices private).
        typename Triangulation<dim>::cell_iterator ancestor = cell;
        while (ancestor->level() > 0)
          ancestor = ancestor->parent();
        return std::binary_search(cells.begin(), cells.end(), static_cast<unsigned int>(ancestor->index()));
      }

    private:
      std::vector<unsigned int> cells; // sorted level-0 indices
    };

    using NodeSetRegion      = MeshSetRegion<SetKind::node_set>;
    using SideSetRegion      = MeshSetRegion<SetKind::side_set>;
    using ElementBlockRegion = MeshSetRegion<SetKind::element_block>;
  } // namespace

  PERIDEAL_REGISTER(RegionSelector, NodeSetRegion, "Node set",
                    "the points of a node set of the mesh file (Discretization/Type = Exodus), by name.")
  PERIDEAL_REGISTER(RegionSelector, SideSetRegion, "Side set",
                    "the points of the elements with a side in a side set of the mesh file, by name.")
  PERIDEAL_REGISTER(RegionSelector, ElementBlockRegion, "Element block",
                    "the points of an element block of the mesh file, by name.")
} // namespace perideal
