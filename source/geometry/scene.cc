// The keys every scene shares (scene.h), the choice of the geometry plugin,
// and the periodicity of the mesh it made.
#include <perideal/geometry/scene.h>

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  void
  Scene::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Type", "Box", Registry<SceneGeometry>::instance().selection(),
                      "The geometry, one of: " + Registry<SceneGeometry>::instance().documentation() +
                        " Each active cell of a peridynamic block becomes one point at its centroid "
                        "with the cell's volume.");
    prm.declare_entry("Horizon",
                      "0",
                      Patterns::Double(0),
                      "The horizon of every block that does not set its own. Bonds "
                      "with |xi| <= horizon*(1+1e-9) are kept, so a neighbor at exactly "
                      "the horizon (e.g. 3.0*h) is never lost to round-off.");
    prm.declare_entry("Partial volumes", "false", Patterns::Bool(),
                      "true: a neighbor counts with the part of its cell inside the horizon sphere, "
                      "computed from the cells' real geometry (trilinear hexahedra), instead of all "
                      "or nothing by its centroid; bonds then also join points whose centroids lie "
                      "up to a cell radius beyond the horizon. Each bond takes the mean of its two "
                      "directions' fractions, so action equals reaction. Smooths the family sums' "
                      "jumps with delta/h (doc/verification.md); costs 4 bytes per bond, more bonds, "
                      "and set-up time.");
    prm.declare_entry("Periodic directions", "", Patterns::List(Patterns::Selection("x|y|z"), 0, 3),
                      "Directions in which the scene repeats, e.g. 'y, z': the mesh's two bounding "
                      "faces normal to each are one face, and a family near one continues through the "
                      "other (minimum-image bonds, no stored copies). The period is the bounding box's "
                      "length and must exceed twice the horizon (plus a cell radius with partial "
                      "volumes); the cells on the two faces must match (a box does). The displacement "
                      "is periodic: a plane wave, a unit cell of a lattice or a laminate, a slab taken "
                      "from an infinite plate. Not with continuum blocks.");
    prm.declare_entry("Refinement regions", "", Patterns::Anything(),
                      "Regions of Discretization/Regions, comma separated: the cells whose centroid lies "
                      "in the i-th are refined as often as the i-th entry of Refinement levels says "
                      "(p4est keeps neighbours within one level). The usual use: fine cells for the "
                      "peridynamic block along a crack path, cells twice as large for the continuum "
                      "cells next to it, coarse cells elsewhere (hanging nodes are constrained).");
    prm.declare_entry("Refinement levels", "", Patterns::List(Patterns::Integer(0, 6)),
                      "One entry per Refinement region.");
    for (const auto &[name, entry] : Registry<SceneGeometry>::instance().all())
      entry.declare(prm);
  }

  void
  Scene::parse_parameters(ParameterHandler &prm)
  {
    type              = prm.get("Type");
    horizon           = prm.get_double("Horizon");
    partial_volumes   = prm.get_bool("Partial volumes");
    periodic          = {{false, false, false}};
    for (const std::string &d : Utilities::split_string_list(prm.get("Periodic directions"), ','))
      {
        const unsigned int k = d[0] - 'x';
        AssertThrow(!periodic[k], ExcMessage("Discretization/Periodic directions: '" + d + "' is given twice"));
        periodic[k] = true;
      }
    refinement_regions = Utilities::split_string_list(prm.get("Refinement regions"), ',');
    for (const int l : Utilities::string_to_int(Utilities::split_string_list(prm.get("Refinement levels"), ',')))
      refinement_levels.push_back(l);
    AssertThrow(refinement_regions.size() == refinement_levels.size(),
                ExcMessage("Discretization/Refinement levels: give one number per entry of Refinement regions"));
    AssertThrow(std::isfinite(horizon),
                ExcMessage("Discretization/Horizon must be finite, got " + Utilities::to_string(horizon)));
    geometry = Registry<SceneGeometry>::instance().create(type, "Discretization/Type");
    geometry->parse_parameters(prm, horizon);
  }

  namespace
  {
    /**
     * Periodic along @p d joins the mesh's faces on the planes x_d = low and
     * x_d = high: they must be copies of each other. The minimum-image bonds
     * do not look at faces, so a mesh without them (a Cylinder shell along x
     * or y) or with faces that do not match ran silently with bonds across
     * the gap. Compares the coarse faces' centres and areas on the two
     * planes (every rank holds the whole coarse mesh: all decide alike).
     */
    void
    check_periodic_faces(const parallel::distributed::Triangulation<dim> &tria,
                         const unsigned int                                d,
                         const double                                      low,
                         const double                                      high)
    {
      const char   axis = char('x' + d);
      const double size = (high - low) + 1e-300;
      double       diameter = 0;
      for (const auto &cell : tria.cell_iterators_on_level(0))
        diameter = std::max(diameter, cell->diameter());
      const double quantum = 1e-6 * std::max(diameter, size);
      // Per plane: the faces' centres in the other two coordinates, and areas.
      std::array<std::vector<std::array<long long, 3>>, 2> faces;
      std::array<std::vector<Point<dim>>, 2>               centres;
      for (const auto &cell : tria.cell_iterators_on_level(0))
        for (const unsigned int f : cell->face_indices())
          if (cell->at_boundary(f))
            {
              const auto face = cell->face(f);
              for (unsigned int side = 0; side < 2; ++side)
                {
                  const double plane = side == 0 ? low : high;
                  bool         on    = true;
                  for (const unsigned int v : face->vertex_indices())
                    on = on && std::abs(face->vertex(v)[d] - plane) <= 1e-8 * size;
                  if (!on)
                    continue;
                  const Point<dim>          c = face->center();
                  std::array<long long, 3> key{};
                  unsigned int              k = 0;
                  for (unsigned int e = 0; e < dim; ++e)
                    if (e != d)
                      key[k++] = std::llround(c[e] / quantum);
                  key[2] = std::llround(face->measure() / (quantum * std::max(diameter, size)));
                  faces[side].push_back(key);
                  centres[side].push_back(c);
                }
            }
      const auto where = [&](const unsigned int side) {
        std::ostringstream s;
        s << axis << " = " << (side == 0 ? low : high);
        return s.str();
      };
      for (unsigned int side = 0; side < 2; ++side)
        AssertThrow(!faces[side].empty(),
                    ExcMessage("Discretization/Periodic directions: '" + std::string(1, axis) +
                               "' joins the mesh's boundary faces on the planes " + where(0) + " and " +
                               where(1) + " (its bounding box), but no boundary face lies on " + where(side) +
                               ": the mesh is not bounded by planes normal to " + std::string(1, axis) +
                               " (a Cylinder shell is periodic along z only): remove '" + std::string(1, axis) +
                               "' from Periodic directions"));
      std::array<std::vector<std::array<long long, 3>>, 2> sorted = faces;
      for (auto &list : sorted)
        std::sort(list.begin(), list.end());
      if (sorted[0] == sorted[1])
        return;
      // The first face of either plane without a copy on the other.
      for (unsigned int side = 0; side < 2; ++side)
        for (unsigned int i = 0; i < faces[side].size(); ++i)
          if (!std::binary_search(sorted[1 - side].begin(), sorted[1 - side].end(), faces[side][i]))
            {
              std::ostringstream at;
              at << "(" << centres[side][i] << ")";
              AssertThrow(false,
                          ExcMessage("Discretization/Periodic directions: along " + std::string(1, axis) +
                                     " the mesh's faces on " + where(0) + " (" + std::to_string(faces[0].size()) +
                                     " faces) and on " + where(1) + " (" + std::to_string(faces[1].size()) +
                                     " faces) do not match: the face centred at " + at.str() + " on " +
                                     where(side) + " has no copy on " + where(1 - side) +
                                     ". A periodic direction needs the two faces to be translated copies "
                                     "(a box is; mesh a Gmsh geometry with 'Periodic Surface'), or remove '" +
                                     std::string(1, axis) + "' from Periodic directions"));
            }
    }
  } // namespace

  Periodicity
  Scene::periodicity(const parallel::distributed::Triangulation<dim> &tria) const
  {
    // Every rank holds the whole coarse mesh, and refinement stays inside it.
    Periodicity result;
    for (unsigned int d = 0; d < dim; ++d)
      if (periodic[d])
        {
          double low = std::numeric_limits<double>::max(), high = -low;
          for (const auto &cell : tria.cell_iterators_on_level(0))
            for (const unsigned int v : cell->vertex_indices())
              {
                low  = std::min(low, cell->vertex(v)[d]);
                high = std::max(high, cell->vertex(v)[d]);
              }
          check_periodic_faces(tria, d, low, high);
          result.set(d, low, high);
        }
    return result;
  }

} // namespace perideal
