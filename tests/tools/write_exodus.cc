// Writes the Exodus II meshes of the tests of Discretization/Type = Exodus
// into the folder given, through the Exodus II library (as Cubit and
// SEACAS write them): restart_verlet.prm's box of 8 x 4 x 4 unit cells on
// [0, 8] x [0, 4] x [0, 4] in blocks 1 (x < 4, named "front") and 2
// (x > 4, unnamed: block_2), with
//   box_hex.g      its 128 hexahedra; node set "left" (the nodes at x = 0),
//                  node set 7 (unnamed: nodelist_7, the nodes at y = 4), side
//                  set 20 "top" (the sides at y = 4)
//   box_distorted.g  the same with the inner nodes moved (faces not planar)
//   box_spheres.g  128 sphere elements at the cell centres (attributes:
//                  radius, volume 1); "left" and nodelist_7 hold the spheres
//                  of the first layer in x and of the last in y
//   box_tets.g     each hexahedron cut into 6 tetrahedra (768)
//   box_split.g.2.0, box_split.g.2.1
//                  box_hex.g decomposed into the blocks (x < 4, x > 4), with
//                  the global node and element numbers as maps
// and bad files: not_netcdf.g (text), truncated.g (half of box_hex.g),
// plane.g (a 2D mesh), hex20.g (a second-order hexahedron), sphere_radius.g
// (sphere elements with one attribute), tangled.g (a twisted hexahedron).

#include <exodusII.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

namespace
{
  const int nx = 8, ny = 4, nz = 4;

  void
  check(const int status, const std::string &what)
  {
    if (status < 0)
      {
        std::cerr << "write_exodus: " << what << " failed (" << status << ")\n";
        std::exit(1);
      }
  }

  int
  create(const std::string &file, const int dimension, const int nodes, const int elements, const int blocks,
         const int node_sets, const int side_sets)
  {
    int       cpu_word = sizeof(double), io_word = 8;
    const int id       = ex_create(file.c_str(), EX_CLOBBER, &cpu_word, &io_word);
    check(id, "ex_create " + file);
    check(ex_put_init(id, "PeriDeal test mesh", dimension, nodes, elements, blocks, node_sets, side_sets), "ex_put_init");
    return id;
  }

  int
  node(const int i, const int j, const int k) // from 1
  {
    return 1 + i + (nx + 1) * (j + (ny + 1) * k);
  }

  struct Cell
  {
    int i, j, k;
  };

  /// The cells of block 1 (x < 4) or 2, in the order k, j, i.
  std::vector<Cell>
  cells_of(const int block)
  {
    std::vector<Cell> cells;
    for (int k = 0; k < nz; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
          if ((i < nx / 2) == (block == 1))
            cells.push_back({i, j, k});
    return cells;
  }

  std::array<int, 8>
  hex_nodes(const Cell &c)
  {
    return {{node(c.i, c.j, c.k), node(c.i + 1, c.j, c.k), node(c.i + 1, c.j + 1, c.k), node(c.i, c.j + 1, c.k),
             node(c.i, c.j, c.k + 1), node(c.i + 1, c.j, c.k + 1), node(c.i + 1, c.j + 1, c.k + 1),
             node(c.i, c.j + 1, c.k + 1)}};
  }

  /// The grid's nodes; @p distorted moves the inner ones by up to 0.15 in
  /// each direction, which makes the cells' faces non-planar.
  void
  put_grid_coordinates(const int id, const bool distorted = false)
  {
    std::vector<double> x, y, z;
    for (int k = 0; k <= nz; ++k)
      for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i)
          {
            const bool   inner = distorted && i > 0 && i < nx && j > 0 && j < ny && k > 0 && k < nz;
            const double shift = inner ? 0.15 * std::sin(1.3 * i + 0.7 * j + 0.4 * k) : 0;
            x.push_back(i + shift), y.push_back(j - shift), z.push_back(k + 0.5 * shift);
          }
    check(ex_put_coord(id, x.data(), y.data(), z.data()), "ex_put_coord");
  }

  void
  put_block(const int id, const int block, const char *type, const int count, const int per_element,
            const std::vector<int> &connectivity, const std::vector<double> &attributes = {}, const int n_attributes = 0)
  {
    check(ex_put_elem_block(id, block, type, count, per_element, n_attributes), "ex_put_elem_block");
    check(ex_put_elem_conn(id, block, connectivity.data()), "ex_put_elem_conn");
    if (n_attributes > 0)
      check(ex_put_elem_attr(id, block, attributes.data()), "ex_put_elem_attr");
    if (block == 1)
      check(ex_put_name(id, EX_ELEM_BLOCK, block, "front"), "ex_put_name");
  }

  void
  put_node_set(const int id, const int set, const char *name, const std::vector<int> &nodes)
  {
    check(ex_put_node_set_param(id, set, nodes.size(), 0), "ex_put_node_set_param");
    if (!nodes.empty())
      check(ex_put_node_set(id, set, nodes.data()), "ex_put_node_set");
    if (name)
      check(ex_put_name(id, EX_NODE_SET, set, name), "ex_put_name");
  }

  /// The grid nodes for which @p in holds.
  std::vector<int>
  grid_nodes(const std::function<bool(int, int, int)> &in)
  {
    std::vector<int> nodes;
    for (int k = 0; k <= nz; ++k)
      for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i)
          if (in(i, j, k))
            nodes.push_back(node(i, j, k));
    return nodes;
  }

  void
  write_hexahedra(const std::string &file, const bool distorted = false)
  {
    const int id = create(file, 3, (nx + 1) * (ny + 1) * (nz + 1), nx * ny * nz, 2, 2, 1);
    put_grid_coordinates(id, distorted);
    std::vector<int> top_elements, top_sides;
    int              number = 0;
    for (const int block : {1, 2})
      {
        std::vector<int> connectivity;
        for (const Cell &c : cells_of(block))
          {
            ++number;
            for (const int n : hex_nodes(c))
              connectivity.push_back(n);
            if (c.j == ny - 1)
              top_elements.push_back(number), top_sides.push_back(3); // Exodus's side 3: y = max
          }
        put_block(id, block, "HEX8", nx * ny * nz / 2, 8, connectivity);
      }
    put_node_set(id, 1, "left", grid_nodes([](int i, int, int) { return i == 0; }));
    put_node_set(id, 7, nullptr, grid_nodes([](int, int j, int) { return j == ny; }));
    check(ex_put_side_set_param(id, 20, top_elements.size(), 0), "ex_put_side_set_param");
    check(ex_put_side_set(id, 20, top_elements.data(), top_sides.data()), "ex_put_side_set");
    check(ex_put_name(id, EX_SIDE_SET, 20, "top"), "ex_put_name");
    check(ex_close(id), "ex_close");
  }

  void
  write_spheres(const std::string &file)
  {
    const int n  = nx * ny * nz;
    const int id = create(file, 3, n, n, 2, 2, 0);
    std::vector<double> x, y, z;
    std::vector<int>    left, back;
    for (const int block : {1, 2})
      for (const Cell &c : cells_of(block))
        {
          x.push_back(c.i + 0.5), y.push_back(c.j + 0.5), z.push_back(c.k + 0.5);
          if (c.i == 0)
            left.push_back(x.size());
          if (c.j == ny - 1)
            back.push_back(x.size());
        }
    check(ex_put_coord(id, x.data(), y.data(), z.data()), "ex_put_coord");
    const double radius = 0.6203504908994; // of a sphere of volume 1
    for (const int block : {1, 2})
      {
        std::vector<int>    connectivity;
        std::vector<double> attributes;
        for (int e = 0; e < n / 2; ++e)
          {
            connectivity.push_back((block - 1) * n / 2 + e + 1);
            attributes.push_back(radius), attributes.push_back(1.0);
          }
        put_block(id, block, "SPHERE", n / 2, 1, connectivity, attributes, 2);
      }
    put_node_set(id, 1, "left", left);
    put_node_set(id, 7, nullptr, back);
    check(ex_close(id), "ex_close");
  }

  void
  write_tetrahedra(const std::string &file)
  {
    const int id = create(file, 3, (nx + 1) * (ny + 1) * (nz + 1), 6 * nx * ny * nz, 2, 0, 0);
    put_grid_coordinates(id);
    // The 6 tetrahedra around the diagonal from corner 0 to corner 6 (in
    // Exodus's hexahedron order), each positively oriented.
    const int tets[6][4] = {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
    for (const int block : {1, 2})
      {
        std::vector<int> connectivity;
        for (const Cell &c : cells_of(block))
          {
            const auto h = hex_nodes(c);
            for (const auto &t : tets)
              {
                // Right-handed: (x1 - x0) . ((x2 - x0) x (x3 - x0)) > 0.
                const auto corner = [](const int v) {
                  return std::array<int, 3>{{(v == 1 || v == 2 || v == 5 || v == 6), (v == 2 || v == 3 || v == 6 || v == 7), v >= 4}};
                };
                const auto a = corner(t[0]), b = corner(t[1]), c = corner(t[2]), d = corner(t[3]);
                int        e[3][3];
                for (int k = 0; k < 3; ++k)
                  e[0][k] = b[k] - a[k], e[1][k] = c[k] - a[k], e[2][k] = d[k] - a[k];
                const int det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                                e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                                e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
                for (const int v : det > 0 ? std::array<int, 4>{{t[0], t[1], t[2], t[3]}} :
                                             std::array<int, 4>{{t[0], t[2], t[1], t[3]}})
                  connectivity.push_back(h[v]);
              }
          }
        put_block(id, block, "TETRA", 3 * nx * ny * nz, 4, connectivity);
      }
    check(ex_close(id), "ex_close");
  }

  void
  write_piece(const std::string &file, const int block)
  {
    // The piece's nodes: those its cells use, numbered locally from 1.
    std::vector<int> local(node(nx, ny, nz) + 1, 0), global;
    std::vector<int> connectivity;
    for (const Cell &c : cells_of(block))
      for (const int n : hex_nodes(c))
        {
          if (local[n] == 0)
            global.push_back(n), local[n] = global.size();
          connectivity.push_back(local[n]);
        }
    const int count = nx * ny * nz / 2;
    const int id    = create(file, 3, global.size(), count, 1, 2, 0);
    std::vector<double> x, y, z;
    for (const int n : global)
      {
        const int m = n - 1;
        x.push_back(m % (nx + 1)), y.push_back((m / (nx + 1)) % (ny + 1)), z.push_back(m / ((nx + 1) * (ny + 1)));
      }
    check(ex_put_coord(id, x.data(), y.data(), z.data()), "ex_put_coord");
    check(ex_put_id_map(id, EX_NODE_MAP, global.data()), "ex_put_id_map");
    std::vector<int> elements(count);
    for (int e = 0; e < count; ++e)
      elements[e] = (block - 1) * count + e + 1;
    check(ex_put_id_map(id, EX_ELEM_MAP, elements.data()), "ex_put_id_map");
    put_block(id, block, "HEX8", count, 8, connectivity);
    std::vector<int> left, back;
    for (const int n : global)
      {
        const int m = n - 1;
        if (m % (nx + 1) == 0)
          left.push_back(local[n]);
        if ((m / (nx + 1)) % (ny + 1) == ny)
          back.push_back(local[n]);
      }
    put_node_set(id, 1, "left", left);
    put_node_set(id, 7, nullptr, back);
    check(ex_close(id), "ex_close");
  }

  void
  write_single(const std::string &file, const int dimension, const char *type, const std::vector<double> &x,
               const std::vector<double> &y, const std::vector<double> &z, const int per_element,
               const int n_attributes = 0)
  {
    const int id = create(file, dimension, x.size(), 1, 1, 0, 0);
    check(ex_put_coord(id, x.data(), y.data(), dimension == 3 ? z.data() : nullptr), "ex_put_coord");
    std::vector<int> connectivity(per_element);
    for (int i = 0; i < per_element; ++i)
      connectivity[i] = i + 1;
    put_block(id, 1, type, 1, per_element, connectivity, std::vector<double>(n_attributes, 1.0), n_attributes);
    check(ex_close(id), "ex_close");
  }

  void
  write_bad_files(const std::string &folder)
  {
    std::ofstream(folder + "/not_netcdf.g") << "this is not a mesh\n";
    {
      std::ifstream     in(folder + "/box_hex.g", std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      std::ofstream(folder + "/truncated.g", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    }
    write_single(folder + "/plane.g", 2, "QUAD4", {0, 1, 1, 0}, {0, 0, 1, 1}, {}, 4);
    std::vector<double> x(20), y(20), z(20);
    for (int i = 0; i < 8; ++i)
      x[i] = (i == 1 || i == 2 || i == 5 || i == 6), y[i] = (i == 2 || i == 3 || i == 6 || i == 7), z[i] = i >= 4;
    for (int i = 8; i < 20; ++i)
      x[i] = 0.5, y[i] = 0.5, z[i] = 0.5; // the mid-edge nodes do not matter here
    write_single(folder + "/hex20.g", 3, "HEX20", x, y, z, 20);
    write_single(folder + "/sphere_radius.g", 3, "SPHERE", {0}, {0}, {0}, 1, 1);
    std::vector<double> tx(x.begin(), x.begin() + 8), ty(y.begin(), y.begin() + 8), tz(z.begin(), z.begin() + 8);
    std::swap(tx[6], tx[7]); // the top face folded over itself
    std::swap(ty[6], ty[7]);
    write_single(folder + "/tangled.g", 3, "HEX8", tx, ty, tz, 8);
  }
} // namespace

int
main(int argc, char **argv)
{
  if (argc != 2)
    {
      std::cerr << "usage: write_exodus FOLDER\n";
      return 2;
    }
  ex_opts(EX_VERBOSE);
  const std::string folder = argv[1];
  write_hexahedra(folder + "/box_hex.g");
  write_hexahedra(folder + "/box_distorted.g", true);
  write_spheres(folder + "/box_spheres.g");
  write_tetrahedra(folder + "/box_tets.g");
  write_piece(folder + "/box_split.g.2.0", 1);
  write_piece(folder + "/box_split.g.2.1", 2);
  write_bad_files(folder);
  return 0;
}
