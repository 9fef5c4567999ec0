// Discretization/Type = Text file: Peridigm's point cloud, a line "x y z
// block volume" per point. Each point becomes a cube of its volume centred on
// it, a coarse cell of its own: the cell's centroid and measure are the
// point's position and volume, its material id the block, so regions,
// conditions, families and output work on a point cloud as on a mesh. The
// cubes are created in the order of a Morton curve through the points, so
// that each rank's share of them is compact in space (p4est partitions the
// coarse cells in their order).

#include <perideal/geometry/scene.h>

#include <deal.II/base/utilities.h>
#include <deal.II/grid/tria_description.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <unordered_map>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class TextFileScene : public SceneGeometry
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.enter_subsection("Text file");
        prm.declare_entry("File", "", Patterns::Anything(),
                          "Peridigm's Text File discretization: a line 'x y z block volume' per point (blank "
                          "lines and '#' comments skipped). Each point becomes a cube of its volume centred on it "
                          "(one cell, one point, as a mesh's): the block is the cell's material id (Blocks/*/"
                          "Material ids, Regions of Type Physical group with dimension 3), and regions, "
                          "conditions and output work as on a mesh. A bad line stops the run with its number. A "
                          "relative path is taken from the directory the run starts in.");
        prm.leave_subsection();
      }

      void
      parse_parameters(ParameterHandler &prm, const double horizon) override
      {
        prm.enter_subsection("Text file");
        file = prm.get("File");
        prm.leave_subsection();
        const std::string key = "Discretization/Text file/File";
        AssertThrow(!file.empty(), ExcMessage(key + " is empty: name the file of points"));
        std::error_code error;
        const auto      status = std::filesystem::status(file, error);
        AssertThrow(std::filesystem::is_regular_file(status),
                    ExcMessage(key + ": '" + file + "' " +
                               (std::filesystem::exists(status) ? "is not a regular file" : "does not exist")));
        std::ifstream in(file);
        AssertThrow(in, ExcMessage(key + ": cannot open '" + file + "'"));
        std::string  line;
        unsigned int number = 0;
        while (std::getline(in, line))
          {
            ++number;
            const std::string text = line.substr(0, line.find('#'));
            if (text.find_first_not_of(" \t\r,") == std::string::npos)
              continue;
            std::istringstream words(text);
            double             x[3], block = 0, volume = 0;
            std::string        rest;
            const bool         read = static_cast<bool>(words >> x[0] >> x[1] >> x[2] >> block >> volume);
            const auto where = [&]() { return key + " '" + file + "', line " + std::to_string(number) + ": "; };
            AssertThrow(read && !(words >> rest),
                        ExcMessage(where() + "expected five numbers 'x y z block volume', got '" +
                                   Utilities::trim(text) + "'"));
            AssertThrow(std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]),
                        ExcMessage(where() + "the position is not finite"));
            AssertThrow(block >= 0 && block == std::floor(block) && block < 1e9,
                        ExcMessage(where() + "the block '" + Utilities::to_string(block) +
                                   "' is not a whole number >= 0"));
            AssertThrow(std::isfinite(volume) && volume > 0,
                        ExcMessage(where() + "the volume '" + Utilities::to_string(volume) +
                                   "' is not finite and positive"));
            const double edge = std::cbrt(volume);
            for (unsigned int d = 0; d < dim; ++d)
              AssertThrow(resolvable(std::abs(x[d]), edge, horizon),
                          ExcMessage(where() + "the point's size (volume^(1/3) = " + Utilities::to_string(edge) +
                                     ") is too small for its coordinates: points would not be told apart in "
                                     "double; move the body near the origin"));
            points.push_back(PointLine{Point<dim>(x[0], x[1], x[2]), static_cast<unsigned int>(block), edge});
          }
        AssertThrow(!points.empty(), ExcMessage(key + " '" + file + "' holds no point"));
      }

      void
      create_triangulation(parallel::distributed::Triangulation<dim> &tria) const override
      {
        // The Morton key of each point in its bounding box (21 bits per axis).
        Point<dim> lo = points[0].x, hi = points[0].x;
        for (const auto &p : points)
          for (unsigned int d = 0; d < dim; ++d)
            {
              lo[d] = std::min(lo[d], p.x[d]);
              hi[d] = std::max(hi[d], p.x[d]);
            }
        const auto morton = [&](const Point<dim> &x) {
          std::uint64_t key = 0;
          for (unsigned int d = 0; d < dim; ++d)
            {
              const double        span = hi[d] - lo[d];
              const std::uint64_t q =
                span > 0 ? std::min<std::uint64_t>((1u << 21) - 1, std::uint64_t((x[d] - lo[d]) / span * (1u << 21))) : 0;
              for (unsigned int b = 0; b < 21; ++b)
                key |= ((q >> b) & 1u) << (3 * b + d);
            }
          return key;
        };
        std::vector<std::pair<std::uint64_t, unsigned int>> order(points.size());
        for (unsigned int i = 0; i < points.size(); ++i)
          order[i] = {morton(points[i].x), i};
        std::sort(order.begin(), order.end());

        // Cubes whose corners coincide to the bit (a lattice of points) share
        // those vertices: the coarse mesh is then connected, as a mesh is.
        // deal.II orders the coarse cells for p4est by their connectivity
        // (SparsityTools::reorder_hierarchical), and cells that share nothing
        // cost it a search each: 10^5 unconnected cubes take 16 s to set up.
        struct Hash
        {
          std::size_t
          operator()(const std::array<double, 3> &x) const
          {
            std::size_t h = 0;
            for (const double c : x)
              h = h * 1000003u ^ std::hash<double>()(c);
            return h;
          }
        };
        std::unordered_map<std::array<double, 3>, unsigned int, Hash> index;
        index.reserve(2 * points.size());
        std::vector<Point<dim>>    vertices;
        std::vector<CellData<dim>> cells(points.size());
        for (unsigned int c = 0; c < order.size(); ++c)
          {
            const PointLine &p = points[order[c].second];
            const double     h = 0.5 * p.edge;
            for (unsigned int v = 0; v < 8; ++v)
              {
                // deal.II's vertex order: x fastest, then y, then z.
                const std::array<double, 3> x{{p.x[0] + (v & 1 ? h : -h), p.x[1] + (v & 2 ? h : -h),
                                               p.x[2] + (v & 4 ? h : -h)}};
                const auto [it, added] = index.emplace(x, vertices.size());
                if (added)
                  vertices.emplace_back(x[0], x[1], x[2]);
                cells[c].vertices[v] = it->second;
              }
            cells[c].material_id = p.block;
          }
        tria.create_triangulation(vertices, cells, SubCellData());
      }

      std::string
      cells_key() const override
      {
        return "Discretization/Text file/File";
      }

    private:
      struct PointLine
      {
        Point<dim>   x;
        unsigned int block;
        double       edge; // of the cube of its volume
      };
      std::string            file;
      std::vector<PointLine> points;
    };
  } // namespace

  PERIDEAL_REGISTER(SceneGeometry, TextFileScene, "Text file",
                    "Peridigm's point cloud: a line 'x y z block volume' per point, each a cube of its volume.")
} // namespace perideal
