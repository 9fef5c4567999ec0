// Discretization/Type = Text file: Peridigm's point cloud, a line "x y z
// block volume" per point. Each point becomes a cube of its volume centred on
// it, a coarse cell of its own (point_cubes.h): the cell's centroid and
// measure are the point's position and volume, its material id the block.

#include <perideal/geometry/point_cubes.h>
#include <perideal/geometry/scene.h>

#include <deal.II/base/utilities.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

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
            points.push_back(CloudPoint{Point<dim>(x[0], x[1], x[2]), volume, static_cast<unsigned int>(block)});
          }
        AssertThrow(!points.empty(), ExcMessage(key + " '" + file + "' holds no point"));
        // In the order create_point_cubes() makes their cells, which then
        // keeps it: point number n (its line among the points) is the cell
        // of sets.point_cells[n - 1], for Regions of Type Point numbers.
        const std::vector<unsigned int> order = morton_order(points);
        std::vector<CloudPoint>         sorted(points.size());
        sets.point_cells.resize(points.size());
        for (unsigned int c = 0; c < order.size(); ++c)
          {
            sorted[c]                    = points[order[c]];
            sets.point_cells[order[c]] = {long(order[c]) + 1, c};
          }
        points = std::move(sorted);
      }

      const MeshSets *
      mesh_sets() const override
      {
        return &sets;
      }

      void
      create_triangulation(parallel::distributed::Triangulation<dim> &tria) const override
      {
        create_point_cubes(tria, points);
      }

      std::string
      cells_key() const override
      {
        return "Discretization/Text file/File";
      }

    private:
      std::string             file;
      std::vector<CloudPoint> points; // in Morton order
      MeshSets                sets;
    };
  } // namespace

  PERIDEAL_REGISTER(SceneGeometry, TextFileScene, "Text file",
                    "Peridigm's point cloud: a line 'x y z block volume' per point, each a cube of its volume.")
} // namespace perideal
