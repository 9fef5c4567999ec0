// Discretization/Type = Exodus: Peridigm's usual mesh, an Exodus II file
// (exodus_file.h). A mesh of hexahedra only becomes a mesh of cells, as a
// Gmsh mesh does (peridynamic points or finite elements, by block); any
// other mesh (sphere elements, tetrahedra, prisms, pyramids, mixed) becomes
// one point per element, as Peridigm makes it. The element blocks are the
// cells' material ids, and the node sets, side sets and blocks are regions
// by name (region_mesh_set.cc).

#include <perideal/base/format.h>
#include <perideal/geometry/element_point.h>
#include <perideal/geometry/exodus_file.h>
#include <perideal/geometry/hexahedron.h>
#include <perideal/geometry/point_cubes.h>
#include <perideal/geometry/scene.h>

#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>
#include <deal.II/grid/tria_description.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    const std::string key = "Discretization/Exodus/Mesh file";

    /// What the scene makes of one Exodus element type.
    struct ElementKind
    {
      bool         sphere = false;
      ElementShape shape  = ElementShape::hexahedron;
    };

    /// The kind of the elements of @p block; refuses the types PeriDeal
    /// cannot read (second-order, 2D), naming the block.
    ElementKind
    element_kind(const ExodusMesh::Block &block, const std::string &where)
    {
      const std::string  &t = block.type;
      const unsigned int  n = block.nodes_per_element;
      const std::string   what = where + ": element block " + std::to_string(block.id) + " ('" + block.name +
                               "') is of type " + t + " with " + std::to_string(n) + " nodes";
      const auto is = [&](std::initializer_list<const char *> names) {
        return std::any_of(names.begin(), names.end(), [&](const char *name) { return t == name; });
      };
      const std::map<ElementShape, unsigned int> corners{{ElementShape::tetrahedron, 4}, {ElementShape::hexahedron, 8},
                                                         {ElementShape::prism, 6}, {ElementShape::pyramid, 5}};
      ElementKind kind;
      if (is({"SPHERE", "SPHERE1"}))
        {
          AssertThrow(n == 1, ExcMessage(what + ": a sphere element has one node"));
          AssertThrow(block.n_attributes >= 2,
                      ExcMessage(what + " and " + std::to_string(block.n_attributes) +
                                 " attributes: a sphere element's volume is its second attribute (after the "
                                 "radius), as Peridigm reads it"));
          kind.sphere = true;
          return kind;
        }
      if (t.rfind("HEX", 0) == 0)
        kind.shape = ElementShape::hexahedron;
      else if (t.rfind("TET", 0) == 0)
        kind.shape = ElementShape::tetrahedron;
      else if (t.rfind("WEDGE", 0) == 0)
        kind.shape = ElementShape::prism;
      else if (t.rfind("PYRAMID", 0) == 0)
        kind.shape = ElementShape::pyramid;
      else
        AssertThrow(false, ExcMessage(what + ", which is not a 3D element: PeriDeal reads SPHERE, HEX8, TETRA4, "
                                              "WEDGE6 and PYRAMID5 elements of 3D meshes"));
      AssertThrow(n == corners.at(kind.shape),
                  ExcMessage(what + (n > corners.at(kind.shape) ?
                                       std::string(", a second-order element: PeriDeal reads first-order elements "
                                                   "only (their corners make the cell); mesh with linear "
                                                   "elements") :
                                       ": too few nodes for the shape")));
      return kind;
    }

    class ExodusScene : public SceneGeometry
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Exodus");
        prm.declare_entry(
          "Mesh file", "", Patterns::Anything(),
          "An Exodus II mesh (.g, .e; Peridigm's Input Mesh File), or the name of one decomposed into pieces "
          "FILE.N.0 ... FILE.N.N-1 (Sandia's decomp), which are read whole, joined by their global node and "
          "element numbers. A mesh of first-order hexahedra (HEX8) only becomes a mesh of cells, as a Gmsh "
          "mesh does (peridynamic points at the cells' centroids with their volumes, or finite elements, by "
          "block; invalid cells refused naming the element); any other mesh (SPHERE elements, whose volume "
          "is the second attribute, TETRA4, WEDGE6, PYRAMID5, or a mix) becomes one point per element at its "
          "centroid with its volume, a cube of that volume as a Text file point is, as Peridigm makes it. "
          "Second-order and 2D elements are refused. An element block with id N is material id N (Blocks/*/"
          "Material ids; Regions of Type Element block by its name or block_N). Node sets are Regions of "
          "Type Node set (an element is in it if one of its nodes is, as Peridigm converts them; a sphere if "
          "its node is), side sets Regions of Type Side set and, in a mesh of cells, boundary ids (the side "
          "set's id, for Regions of Type Physical group with dimension 2; sides between two cells are "
          "skipped). A relative path is taken from the directory the run starts in.");
        prm.declare_entry("Cells as points", "false", Patterns::Bool(),
                          "true: also a mesh of hexahedra becomes one point per element (a cube of its volume "
                          "at its centroid), as Peridigm reads it, instead of a mesh of cells; false: only a "
                          "mesh with elements other than hexahedra does.");
        prm.leave_subsection();
      }

      void
      parse_parameters(ParameterHandler &prm, const double scene_horizon) override
      {
        prm.enter_subsection("Exodus");
        const std::string file      = prm.get("Mesh file");
        const bool        as_points = prm.get_bool("Cells as points");
        prm.leave_subsection();
        AssertThrow(!file.empty(), ExcMessage(key + " is empty: name the Exodus mesh"));
        horizon               = scene_horizon;
        const ExodusMesh mesh = read_exodus_file(file, key);
        where                 = key + " '" + file + "'";
        elements_of_blocks(mesh);
        const bool all_hexahedra =
          std::all_of(kinds.begin(), kinds.end(),
                      [](const ElementKind &k) { return !k.sphere && k.shape == ElementShape::hexahedron; });
        std::vector<unsigned int> cell_of_element;
        if (all_hexahedra && !as_points)
          cell_of_element = make_cells(mesh);
        else
          cell_of_element = make_points(mesh);
        make_sets(mesh, cell_of_element);
      }

      void
      create_triangulation(parallel::distributed::Triangulation<dim> &tria) const override
      {
        if (!points.empty())
          {
            create_point_cubes(tria, points);
            return;
          }
        tria.create_triangulation(vertices, cells, SubCellData());
        set_side_set_boundary_ids(tria);
      }

      const MeshSets *
      mesh_sets() const override
      {
        return &sets;
      }

      std::string
      cells_key() const override
      {
        return key;
      }

    private:
      /// The elements of all blocks in one list (the order of the blocks,
      /// then of the element numbers): the kind of each block, the block and
      /// the global number of each element.
      void
      elements_of_blocks(const ExodusMesh &mesh)
      {
        for (unsigned int b = 0; b < mesh.blocks.size(); ++b)
          {
            const ExodusMesh::Block &block = mesh.blocks[b];
            AssertThrow(block.id >= 0 && block.id < long(numbers::invalid_material_id),
                        ExcMessage(where + ": element block id " + std::to_string(block.id) +
                                   " is not a valid block number (a whole number >= 0)"));
            kinds.push_back(block.numbers.empty() ? ElementKind() : element_kind(block, where));
            for (const long number : block.numbers)
              element_block.push_back(b), element_number.push_back(number);
          }
        AssertThrow(!element_block.empty(), ExcMessage(where + " holds no elements"));
      }

      /// The index of element @p e (in the list) in its block.
      std::size_t
      index_in_block(const std::size_t e) const
      {
        return e - first_element_of(element_block[e]);
      }

      /// The nodes of element @p e (in the list) of @p mesh.
      std::vector<long>
      element_nodes(const ExodusMesh &mesh, const std::size_t e) const
      {
        const ExodusMesh::Block &block = mesh.blocks[element_block[e]];
        const std::size_t        k     = index_in_block(e);
        return {block.connectivity.begin() + k * block.nodes_per_element,
                block.connectivity.begin() + (k + 1) * block.nodes_per_element};
      }

      std::size_t
      first_element_of(const unsigned int block) const
      {
        return std::lower_bound(element_block.begin(), element_block.end(), block) - element_block.begin();
      }

      std::string
      element_name(const std::size_t e, const ExodusMesh &mesh) const
      {
        const ExodusMesh::Block &block = mesh.blocks[element_block[e]];
        return where + ": element " + std::to_string(element_number[e]) + " (a " +
               (kinds[element_block[e]].sphere ? std::string("sphere") : shape_name(kinds[element_block[e]].shape)) +
               " of block " + std::to_string(block.id) + ")";
      }

      /// Every element one point, in the order create_point_cubes() makes
      /// their cells; returns the cell of each element.
      std::vector<unsigned int>
      make_points(const ExodusMesh &mesh)
      {
        std::vector<CloudPoint> list;
        for (std::size_t e = 0; e < element_block.size(); ++e)
          {
            const ExodusMesh::Block &block = mesh.blocks[element_block[e]];
            const std::size_t        k     = index_in_block(e);
            const std::vector<long>  nodes = element_nodes(mesh, e);
            const ElementKind        kind  = kinds[element_block[e]];
            CloudPoint               p;
            if (kind.sphere)
              {
                const double volume = block.attributes[k * block.n_attributes + 1];
                AssertThrow(std::isfinite(volume) && volume > 0,
                            ExcMessage(element_name(e, mesh) + ": its volume (second attribute) " + sci(volume, 6) +
                                       " is not finite and positive"));
                p = {mesh.nodes[nodes[0]], volume, static_cast<unsigned int>(block.id)};
              }
            else
              {
                std::vector<Point<dim>> corners;
                std::vector<long>       numbers;
                for (const long n : nodes)
                  corners.push_back(mesh.nodes[n]), numbers.push_back(n + 1);
                p = element_as_point(kind.shape, corners, numbers, element_name(e, mesh), false,
                                     static_cast<unsigned int>(block.id));
              }
            const double edge = std::cbrt(p.volume);
            for (unsigned int d = 0; d < dim; ++d)
              AssertThrow(resolvable(std::abs(p.x[d]), edge, horizon),
                          ExcMessage(element_name(e, mesh) + " is too small (volume^(1/3) = " + sci(edge, 6) +
                                     ") for its coordinates: points would not be told apart in double; move the "
                                     "body near the origin"));
            list.push_back(p);
          }
        const std::vector<unsigned int> order = morton_order(list);
        std::vector<unsigned int>       cell_of_element(list.size());
        points.reserve(list.size());
        for (unsigned int c = 0; c < order.size(); ++c)
          {
            points.push_back(list[order[c]]);
            cell_of_element[order[c]] = c;
          }
        return cell_of_element;
      }

      /// Every element one hexahedral cell, in the order of the elements;
      /// refuses invalid cells. Returns the cell of each element.
      std::vector<unsigned int>
      make_cells(const ExodusMesh &mesh)
      {
        // deal.II's vertex order from Exodus's: Exodus goes around each face.
        constexpr std::array<unsigned int, 8> exodus_vertex = {{0, 1, 3, 2, 4, 5, 7, 6}};
        for (std::size_t e = 0; e < element_block.size(); ++e)
          {
            const std::vector<long> nodes = element_nodes(mesh, e);
            CellData<dim>           cell;
            std::array<Point<dim>, 8> v;
            for (unsigned int c = 0; c < 8; ++c)
              {
                const long node       = nodes[exodus_vertex[c]];
                const auto [it, added] = vertex_of_node.emplace(node, vertices.size());
                if (added)
                  vertices.push_back(mesh.nodes[node]);
                cell.vertices[c] = it->second;
                v[c]             = mesh.nodes[node];
              }
            check_hexahedron(v, e, mesh);
            cell.material_id = static_cast<types::material_id>(mesh.blocks[element_block[e]].id);
            cells.push_back(cell);
          }
        // Left-handed cells are fine (deal.II turns them), as in a Gmsh mesh.
        GridTools::invert_all_negative_measure_cells(vertices, cells);
        GridTools::consistently_order_cells(cells);
        std::vector<unsigned int> cell_of_element(cells.size());
        for (unsigned int e = 0; e < cell_of_element.size(); ++e)
          cell_of_element[e] = e;
        return cell_of_element;
      }

      /// Refuses a hexahedron whose Jacobian is zero or changes sign (at the
      /// corners and the Gauss points): twisted, folded or flat.
      void
      check_hexahedron(const std::array<Point<dim>, 8> &v, const std::size_t e, const ExodusMesh &mesh) const
      {
        if (hex_jacobians(v).one_sign)
          return;
        Point<dim> mean;
        for (const auto &p : v)
          mean += p / 8;
        AssertThrow(false,
                    ExcMessage(element_name(e, mesh) + " at (" + sci(mean[0], 6) + " " + sci(mean[1], 6) + " " +
                               sci(mean[2], 6) + ") is invalid: its Jacobian is zero or changes sign in the cell "
                               "(a twisted, folded or flat cell, or a wrong node order): fix the mesh"));
      }

      /// The node sets, side sets and blocks as sets of cells.
      void
      make_sets(const ExodusMesh &mesh, const std::vector<unsigned int> &cell_of_element)
      {
        std::map<long, std::size_t> element_of_number;
        for (std::size_t e = 0; e < element_number.size(); ++e)
          element_of_number[element_number[e]] = e;
        // Peridigm numbers its points by the elements' global ids.
        for (std::size_t e = 0, b = 0; b < mesh.blocks.size(); ++b)
          for (const long id : mesh.blocks[b].ids)
            sets.point_cells.emplace_back(id, cell_of_element[e++]);
        std::sort(sets.point_cells.begin(), sets.point_cells.end());
        for (std::size_t k = 1; k < sets.point_cells.size(); ++k)
          AssertThrow(sets.point_cells[k].first != sets.point_cells[k - 1].first,
                      ExcMessage(where + ": the element map gives the id " +
                                 std::to_string(sets.point_cells[k].first) + " twice"));
        // The elements of each node, for the node sets.
        std::vector<std::vector<unsigned int>> cells_of_node(mesh.nodes.size());
        for (std::size_t e = 0; e < element_block.size(); ++e)
          {
            for (const long n : element_nodes(mesh, e))
              cells_of_node[n].push_back(cell_of_element[e]);
          }
        const auto finish = [](std::vector<unsigned int> &list) {
          std::sort(list.begin(), list.end());
          list.erase(std::unique(list.begin(), list.end()), list.end());
        };
        for (const auto &s : mesh.node_sets)
          {
            auto &list = sets.node_sets[s.name];
            for (const long n : s.items)
              list.insert(list.end(), cells_of_node[n].begin(), cells_of_node[n].end());
            finish(list);
            if (s.name != "nodelist_" + std::to_string(s.id))
              sets.node_sets.emplace("nodelist_" + std::to_string(s.id), list);
          }
        for (const auto &s : mesh.side_sets)
          {
            auto &list = sets.side_sets[s.name];
            for (std::size_t k = 0; k < s.items.size(); ++k)
              {
                const auto it = element_of_number.find(s.items[k]);
                AssertThrow(it != element_of_number.end(),
                            ExcMessage(where + ": side set " + std::to_string(s.id) + " names element " +
                                       std::to_string(s.items[k]) + ", which no block holds"));
                list.push_back(cell_of_element[it->second]);
                if (!cells.empty())
                  sides.push_back({it->second, s.sides[k], s.id});
              }
            finish(list);
            if (s.name != "surfacelist_" + std::to_string(s.id))
              sets.side_sets.emplace("surfacelist_" + std::to_string(s.id), list);
          }
        for (unsigned int b = 0; b < mesh.blocks.size(); ++b)
          {
            const ExodusMesh::Block &block = mesh.blocks[b];
            auto                    &list  = sets.element_blocks[block.name];
            const std::size_t        first = first_element_of(b);
            for (std::size_t e = first; e < first + block.numbers.size(); ++e)
              list.push_back(cell_of_element[e]);
            finish(list);
            if (block.name != "block_" + std::to_string(block.id))
              sets.element_blocks.emplace("block_" + std::to_string(block.id), list);
          }
        if (!cells.empty())
          for (auto &side : sides)
            side.nodes = side_nodes(mesh, side.element, side.side);
      }

      /// The vertices (of the cells made) of side @p side (from 1) of the
      /// hexahedron @p e, in Exodus's side numbering.
      std::array<unsigned int, 4>
      side_nodes(const ExodusMesh &mesh, const std::size_t e, const int side) const
      {
        static constexpr unsigned int exodus_sides[6][4] = {
          {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {0, 4, 7, 3}, {0, 3, 2, 1}, {4, 5, 6, 7}};
        AssertThrow(side >= 1 && side <= 6,
                    ExcMessage(element_name(e, mesh) + ": a side set names its side " + std::to_string(side) +
                               ", and a hexahedron has sides 1 to 6"));
        const std::vector<long>     nodes = element_nodes(mesh, e);
        std::array<unsigned int, 4> result;
        for (unsigned int i = 0; i < 4; ++i)
          result[i] = vertex_of_node.at(nodes[exodus_sides[side - 1][i]]);
        return result;
      }

      /// The side sets' ids on the boundary faces they name; sides between
      /// two cells are no boundary and keep none.
      void
      set_side_set_boundary_ids(Triangulation<dim> &tria) const
      {
        for (const auto &side : sides)
          {
            // The coarse cells are in the order of the elements.
            const typename Triangulation<dim>::cell_iterator cell(&tria, 0, side.element);
            std::set<unsigned int> wanted(side.nodes.begin(), side.nodes.end());
            for (const unsigned int f : cell->face_indices())
              {
                std::set<unsigned int> face;
                for (const unsigned int v : cell->face(f)->vertex_indices())
                  face.insert(cell->face(f)->vertex_index(v));
                if (face == wanted && cell->face(f)->at_boundary())
                  cell->face(f)->set_boundary_id(static_cast<types::boundary_id>(side.id));
              }
          }
      }

      std::string  where;
      double       horizon = 0;
      std::vector<ElementKind>  kinds;          // of each block
      std::vector<unsigned int> element_block;  // of each element
      std::vector<long>         element_number; // of each element
      MeshSets                  sets;
      // A mesh of points:
      std::vector<CloudPoint> points;
      // A mesh of cells:
      std::vector<Point<dim>>    vertices;
      std::vector<CellData<dim>> cells;
      std::map<long, unsigned int> vertex_of_node; // of the nodes the cells use
      struct Side
      {
        std::size_t                 element;
        int                         side;
        long                        id;
        std::array<unsigned int, 4> nodes{};
      };
      std::vector<Side> sides;
    };
  } // namespace

  PERIDEAL_REGISTER(SceneGeometry, ExodusScene, "Exodus",
                    "an Exodus II mesh (Peridigm's): hexahedra as cells, other elements one point each.")
} // namespace perideal
