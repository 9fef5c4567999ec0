// A Gmsh mesh file's nodes and elements as written (ASCII, format 2.2 or
// 4.1), for the checks before deal.II reads a hexahedral mesh and for the
// cells read as points, which deal.II cannot read.

#include <perideal/geometry/gmsh_file.h>

#include <deal.II/base/tensor.h>
#include <deal.II/base/utilities.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    std::vector<std::string>
    tokens(const std::string &line)
    {
      std::istringstream       in(line);
      std::vector<std::string> t;
      for (std::string w; in >> w;)
        t.push_back(w);
      return t;
    }
  } // namespace

  bool
  read_gmsh_file(const std::string &file, GmshMesh &mesh)
  {
    std::ifstream in(file);
    std::string   line;
    int           major = 0;
    // Format 4.1: the physical group of each entity (dimension, tag), as
    // deal.II takes it: the first one, 0 if none.
    std::map<std::pair<int, long>, long> physical;
    auto next = [&in, &line]() -> bool {
      while (std::getline(in, line))
        if (!Utilities::trim(line).empty())
          return true;
      return false;
    };
    // The next line's words, inside a section: a file that ends there is
    // not a mesh (caught below, as a number that does not parse is).
    auto row = [&next, &line]() {
      if (!next())
        throw std::runtime_error("the file ends inside a section");
      return tokens(line);
    };
    try
      {
        while (next())
          {
            const std::string section = Utilities::trim(line);
            if (section == "$MeshFormat")
              {
                const auto t = row();
                if (t.size() < 2 || t[1] != "0")
                  return false; // binary
                major = static_cast<int>(std::stod(t[0]));
                if (major != 2 && major != 4)
                  return false;
              }
            else if (section == "$Entities" && major == 4)
              {
                const auto counts = row();
                for (int d = 0; d < 4; ++d)
                  for (long i = 0; i < std::stol(counts.at(d)); ++i)
                    {
                      // tag, then a point's x y z or a box's 6 coordinates
                      const auto        t = row();
                      const std::size_t n = d == 0 ? 4 : 7;
                      physical[{d, std::stol(t.at(0))}] = std::stol(t.at(n)) > 0 ? std::stol(t.at(n + 1)) : 0;
                    }
              }
            else if (section == "$Nodes" && major == 2)
              {
                const long n = std::stol(row().at(0));
                for (long i = 0; i < n; ++i)
                  {
                    const auto t = row();
                    if (t.size() < 4)
                      return false;
                    mesh.nodes[std::stol(t[0])] = Point<dim>(std::stod(t[1]), std::stod(t[2]), std::stod(t[3]));
                  }
              }
            else if (section == "$Nodes" && major == 4)
              {
                const long blocks = std::stol(row().at(0));
                for (long b = 0; b < blocks; ++b)
                  {
                    const auto head       = row();
                    const int  entity_dim = std::stoi(head.at(0)), parametric = std::stoi(head.at(2));
                    const long n          = std::stol(head.at(3));
                    std::vector<long> tags(n);
                    for (long i = 0; i < n; ++i)
                      {
                        tags[i] = std::stol(row().at(0));
                      }
                    for (long i = 0; i < n; ++i)
                      {
                        const auto t = row();
                        if (t.size() < 3u + (parametric ? entity_dim : 0))
                          return false;
                        mesh.nodes[tags[i]] = Point<dim>(std::stod(t[0]), std::stod(t[1]), std::stod(t[2]));
                      }
                  }
              }
            else if (section == "$Elements" && major == 2)
              {
                const long n = std::stol(row().at(0));
                for (long i = 0; i < n; ++i)
                  {
                    const auto t = row();
                    if (t.size() < 3 || t.size() < 3 + std::stoul(t[2]))
                      return false;
                    // The first tag is the physical group.
                    GmshMesh::Element e{std::stol(t[0]), std::stoi(t[1]), std::stoul(t[2]) > 0 ? std::stol(t[3]) : 0, {}};
                    for (std::size_t k = 3 + std::stoul(t[2]); k < t.size(); ++k)
                      e.nodes.push_back(std::stol(t[k]));
                    mesh.elements.push_back(std::move(e));
                  }
              }
            else if (section == "$Elements" && major == 4)
              {
                const long blocks = std::stol(row().at(0));
                for (long b = 0; b < blocks; ++b)
                  {
                    const auto head  = row();
                    const auto group = physical.find({std::stoi(head.at(0)), std::stol(head.at(1))});
                    const int  type  = std::stoi(head.at(2));
                    const long n     = std::stol(head.at(3));
                    for (long i = 0; i < n; ++i)
                      {
                        const auto t = row();
                        if (t.empty())
                          return false;
                        GmshMesh::Element e{std::stol(t[0]), type, group != physical.end() ? group->second : 0, {}};
                        for (std::size_t k = 1; k < t.size(); ++k)
                          e.nodes.push_back(std::stol(t[k]));
                        mesh.elements.push_back(std::move(e));
                      }
                  }
              }
          }
      }
    catch (const std::exception &)
      {
        return false;
      }
    return major != 0;
  }
} // namespace perideal
