#include <perideal/geometry/region.h>

#include <deal.II/base/utilities.h>

namespace perideal
{
  using namespace dealii;

  void
  Region::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Type", "Box", Patterns::Selection("All|Box|Expression|Physical group"),
                      "How the region is chosen. A point (cell centroid) is in a Box "
                      "if every coordinate lies in [lower, upper] (bounds included); "
                      "in an Expression region where the expression in x, y, z is "
                      "non-zero; in a Physical group region if its cell carries that "
                      "volume group (material id), or, for a surface group, if a face "
                      "of its cell lies on that boundary.");
    prm.declare_entry("Lower corner", "0,0,0", Patterns::List(Patterns::Double(), 3, 3), "Box: x,y,z of the lower corner.");
    prm.declare_entry("Upper corner", "0,0,0", Patterns::List(Patterns::Double(), 3, 3), "Box: x,y,z of the upper corner.");
    prm.declare_entry("Expression", "1", Patterns::Anything(), "Expression: muparser expression in x, y, z; non-zero means inside, e.g. 'x < 0.01 && y > 0'.");
    prm.declare_entry("Physical group", "1", Patterns::Integer(0), "Physical group: the Gmsh physical tag.");
    prm.declare_entry("Physical group dimension", "3", Patterns::Integer(2, 3), "Physical group: 3 for a volume group, 2 for a surface group.");
  }

  void
  Region::parse_parameters(ParameterHandler &prm, const std::string &path)
  {
    type = prm.get("Type");
    lower = get_point(prm, "Lower corner");
    upper = get_point(prm, "Upper corner");
    if (type == "Box")
      for (unsigned int d = 0; d < dim; ++d)
        AssertThrow(upper[d] >= lower[d],
                    ExcMessage(path + ": the upper corner must not be below the "
                                      "lower corner"));
    if (type == "Expression")
      expression = std::make_unique<Expression>(prm.get("Expression"),
                                                path + "/Expression");
    group_id        = prm.get_integer("Physical group");
    group_dimension = prm.get_integer("Physical group dimension");
  }

  bool
  Region::contains(const Point<dim>                               &x,
                   const DoFHandler<dim>::active_cell_iterator &cell) const
  {
    if (type == "All")
      return true;
    if (type == "Box")
      {
        for (unsigned int d = 0; d < dim; ++d)
          if (x[d] < lower[d] || x[d] > upper[d])
            return false;
        return true;
      }
    if (type == "Expression")
      return expression->value(x, 0) != 0;
    if (group_dimension == 3)
      return cell->material_id() == group_id;
    for (const unsigned int f : cell->face_indices())
      if (cell->at_boundary(f) && cell->face(f)->boundary_id() == group_id)
        return true;
    return false;
  }
} // namespace perideal
