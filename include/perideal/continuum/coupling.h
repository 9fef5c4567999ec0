#pragma once
// The coupling of continuum (FE) blocks with peridynamic ones
// (doc/coupling.md): the FE field of the continuum blocks, the virtual points
// through which PD families reach into FE cells, the FE field interpolated
// there (Pi U) and their forces taken back to the FE nodes (Pi^T). Made only
// for a scene with a continuum block.

#include <perideal/continuum/continuum_field.h>
#include <perideal/discretization/discretization.h>

#include <vector>

namespace perideal
{
  /// Force blending's residual at one FE DoF of a node (coupling.h): alpha
  /// M/rho times the node point's PD force density plus 1 - alpha times the
  /// FE force, i.e. @p weight = alpha M/(rho V_p) times the point's V f.
  struct NodeRow
  {
    unsigned int fe_dof; // local (owned) FE DoF
    unsigned int pd_dof; // the node point's local PD DoF, dim i + d
    double       alpha;
    double       weight;
  };

  class Coupling
  {
  public:
    /// The FE field on the continuum cells of @p discretization, its mass and
    /// stiffness (weighted by the blending band), and the virtual points. Collective.
    void
    setup(const Discretization &discretization, const MPI_Comm comm);

    /// The FE field at the virtual points into @p displacement (U's ghosts updated first).
    void
    update_virtual_points(VectorType &displacement);

    /// The FE nodes' forces, continuum.F. Energy blending: the virtual
    /// points' forces (V f of @p force, a density) go to the FE nodes
    /// (Pi^T), with the FE stiffness's. Force blending: the force on a node
    /// of weight alpha is alpha M/rho times the PD force density at its
    /// node point plus 1 - alpha times the FE force (-K U), loads added.
    void
    transfer_forces(const PointCloud &cloud, const VectorType &force);

    /// Force blending: per FE DoF of a node with a node point, its row
    /// (NodeRow); empty with energy blending.
    std::vector<NodeRow>
    node_rows(const PointCloud &cloud) const;

    ContinuumField            continuum;
    std::vector<unsigned int> virtual_points; // owned virtual points (local index)
    std::vector<double>       node_density;   // per continuum node: the density of its block

  private:
    /// Force blending: a node point and its node.
    struct NodePoint
    {
      unsigned int point;    // owned point index
      unsigned int dof[dim]; // local (owned) FE DoF indices
      double       alpha;    // PD weight
      double       volume;   // lumped mass / density
    };
    std::vector<NodePoint> node_points; // empty: energy blending
    bool                   force_blending = false;
    std::vector<double>    u_virtual, f_virtual;
  };
} // namespace perideal
