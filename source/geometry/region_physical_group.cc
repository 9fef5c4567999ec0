// Region Type = Physical group: the cells of a Gmsh volume group, or the
// cells with a face on a surface group.
#include <perideal/geometry/region.h>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    class PhysicalGroupRegion : public RegionSelector
    {
    public:
      static void
      declare_parameters(ParameterHandler &prm)
      {
        prm.declare_entry("Physical group", "1", Patterns::Integer(0), "Physical group: the Gmsh physical tag.");
        prm.declare_entry("Physical group dimension", "3", Patterns::Integer(2, 3), "Physical group: 3 for a volume group, 2 for a surface group.");
      }

      void
      parse_parameters(ParameterHandler &prm, const std::string &, const SceneGeometry &) override
      {
        group_id        = prm.get_integer("Physical group");
        group_dimension = prm.get_integer("Physical group dimension");
      }

      bool
      contains(const Point<dim> &, const DoFHandler<dim>::active_cell_iterator &cell) const override
      {
        if (group_dimension == 3)
          return cell->material_id() == group_id;
        for (const unsigned int f : cell->face_indices())
          if (cell->at_boundary(f) && cell->face(f)->boundary_id() == group_id)
            return true;
        return false;
      }

    private:
      unsigned int group_id = 0, group_dimension = 3;
    };
  } // namespace

  PERIDEAL_REGISTER(RegionSelector, PhysicalGroupRegion, "Physical group",
                    "a point is in a Physical group region if its cell carries that volume group (material "
                    "id), or, for a surface group, if a face of its cell lies on that boundary.")
} // namespace perideal
