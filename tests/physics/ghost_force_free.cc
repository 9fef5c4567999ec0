// The force-blending coupling under affine fields (Coupling/Scheme = force
// blending, doc/coupling.md): a box of FE cells with a cube of PD cells in
// it, u = H x with H each of the six unit strains and their sum (times
// eps = 1e-4) at every point and FE node, the forces evaluated once.
// Checked, per case (PMB, LPS, Elastic correspondence; FE_Q(1), FE_Q(2);
// blending bands of 1 and 2 horizons; with hanging nodes from a refined
// cube around the PD cells):
// - every PD point and free FE node farther than two horizons and a cell
//   from the outer boundary feels |V f| < 1e-10 E eps h^2 (E the Young's
//   modulus, h the PD spacing);
// - the forces of all points and nodes sum to zero to 1e-12 of the sum of
//   their sizes.
// For comparison, the same scenes with energy blending (PMB, LPS) print
// their largest ghost force in units of E eps h^2 (doc/coupling.md), and
// must exceed 1e-3: the check tells the two schemes apart.
// Prints PASS/FAIL per check and ALL PASSED.

#include <perideal/discretization/discretization.h>
#include <perideal/model/force_model.h>
#include <perideal/simulation/simulation.h>

#include <deal.II/base/mpi.h>

#include <array>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

using namespace perideal;

namespace
{
  struct Case
  {
    std::string material, scheme;
    unsigned    degree;
    double      band;
    bool        hanging;
  };

  const double K = 1, G = 0.6, E = 9 * K * G / (3 * K + G), eps = 1e-4;

  /// Half the box's edge: [-9, 9]^3 of cells of size 1; with hanging nodes
  /// [-10, 10]^3 of cells of size 2 (their vertices on even numbers),
  /// refined once in the cube [-4, 4]^3. A checked node is at most 9 - 4.02
  /// from the centre, so its family and its neighbors' stay inside.
  int
  half(const Case &c)
  {
    return c.hanging ? 10 : 9;
  }

  /// The deck: the box (centred: the round-off of positions grows with
  /// their size), PD cells in [-2, 2]^3, horizon 1.51.
  std::string
  deck(const Case &c, const std::string &name)
  {
    std::ostringstream s;
    const std::string model = c.material == "correspondence" ? "Elastic correspondence" : c.material;
    s << "subsection Discretization\n  set Type = Box\n  set Horizon = 1.51\n  subsection Box\n"
      << "    set Lower corner = " << -half(c) << ", " << -half(c) << ", " << -half(c) << "\n"
      << "    set Upper corner = " << half(c) << ", " << half(c) << ", " << half(c) << "\n"
      << "    set Subdivisions = " << (c.hanging ? "10, 10, 10" : "18, 18, 18") << "\n  end\n"
      << "  subsection Regions\n    set Names = pd, fine\n"
      << "    subsection pd\n      set Type = Box\n      set Lower corner = -2, -2, -2\n"
      << "      set Upper corner = 2, 2, 2\n    end\n"
      << "    subsection fine\n      set Type = Box\n      set Lower corner = -4, -4, -4\n"
      << "      set Upper corner = 4, 4, 4\n    end\n  end\n";
    if (c.hanging)
      s << "  set Refinement regions = fine\n  set Refinement levels = 1\n";
    s << "end\nsubsection Materials\n  set Names = solid\n  subsection solid\n    set Model = " << model
      << "\n    set Density = 1\n    set Bulk modulus = " << K << "\n    set Shear modulus = " << G
      << "\n  end\nend\n"
      << "subsection Blocks\n  set Names = pd, fe\n  subsection pd\n    set Material = solid\n"
      << "    set Region = pd\n  end\n  subsection fe\n    set Material = solid\n    set Region = All\n"
      << "    set Type = Continuum\n    set FE degree = " << c.degree << "\n  end\nend\n"
      << "subsection Coupling\n  set Scheme = " << c.scheme << "\n  set Blending width = " << c.band
      << "\nend\nsubsection Solver\n  set Number of steps = 1\n  set Final time = 1e-9\nend\n"
      << "subsection Output\n  set Base name = " << name << "\n  set Frequency = 0\n  set Variables =\nend\n";
    return s.str();
  }

  /// u = eps H x: H the unit strain @p mode (0..5: xx, yy, zz, xy, yz, zx; 6: their sum).
  double
  affine(const unsigned int mode, const dealii::Point<dim> &x, const unsigned int component)
  {
    static const unsigned int pair[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {2, 0}};
    double                    u          = 0;
    for (unsigned int m = 0; m < 6; ++m)
      if (mode == m || mode == 6)
        {
          const unsigned int a = pair[m][0], b = pair[m][1];
          if (component == a)
            u += (a == b ? 1.0 : 0.5) * x[b];
          if (component == b && a != b)
            u += 0.5 * x[a];
        }
    return eps * u;
  }

  struct Result
  {
    double pd = 0, fe = 0, balance = 0; // largest |V f| / (E eps h^2) at PD points, FE nodes; |sum| / sum |V f|
  };

  Result
  measure(const Case &c, const std::string &file, const MPI_Comm comm)
  {
    Simulation simulation(file, comm);
    simulation.dry_run();
    SimulatorAccess  access = simulation.access();
    MechanicalState &state  = access.state;
    const double     h = 1, horizon = 1.51, L = half(c);
    Result           result;
    for (unsigned int mode = 0; mode < 7; ++mode)
      {
        // Free DoFs (FE DoFs of PD cells and hanging ones count as hanging);
        // hanging nodes follow their masters.
        for (unsigned int k = 0; k < state.size(); ++k)
          if (!state.is_virtual(k) && !state.is_hanging(k))
            state.u(k) = affine(mode, state.position(k), state.component(k));
        state.distribute_displacement();
        access.update_ghosts();
        access.model.compute_forces(false);
        std::array<double, dim> sum{};
        double                  size = 0, pd = 0, fe = 0;
        for (unsigned int k = 0; k < state.size(); ++k)
          if (!state.is_virtual(k) && !state.is_hanging(k))
            {
              const double f = state.measure(k) * state.f(k);
              sum[state.component(k)] += f;
              size += std::abs(f);
              const auto   x = state.position(k);
              double       to_boundary = L;
              for (unsigned int d = 0; d < dim; ++d)
                to_boundary = std::min(to_boundary, L - std::abs(x[d]));
              if (to_boundary > 2 * horizon + (c.hanging ? 2 : 1) * h)
                (state.is_fe(k) ? fe : pd) = std::max(state.is_fe(k) ? fe : pd, std::abs(f));
            }
        dealii::Utilities::MPI::sum(dealii::ArrayView<const double>(sum.data(), dim), comm,
                                    dealii::ArrayView<double>(sum.data(), dim));
        size = dealii::Utilities::MPI::sum(size, comm);
        const double scale = E * eps * h * h;
        result.pd          = std::max(result.pd, dealii::Utilities::MPI::max(pd, comm) / scale);
        result.fe          = std::max(result.fe, dealii::Utilities::MPI::max(fe, comm) / scale);
        for (const double s : sum)
          result.balance = std::max(result.balance, std::abs(s) / size);
      }
    return result;
  }
} // namespace

int
main(int argc, char *argv[])
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                           comm = MPI_COMM_WORLD;
  const bool                               root = dealii::Utilities::MPI::this_mpi_process(comm) == 0;
  // G = 3K/5: Poisson's ratio 1/4, which PMB needs.
  const std::vector<Case>                  cases{
    {"PMB", "force blending", 1, 1, false},       {"PMB", "force blending", 2, 2, false},
    {"PMB", "force blending", 1, 2, true},        {"PMB", "force blending", 2, 1, true},
    {"LPS", "force blending", 1, 1, false},       {"LPS", "force blending", 2, 2, false},
    {"LPS", "force blending", 1, 2, true},        {"LPS", "force blending", 2, 1, true},
    {"correspondence", "force blending", 1, 1, false}, {"correspondence", "force blending", 2, 2, false},
    {"correspondence", "force blending", 1, 2, true},  {"correspondence", "force blending", 2, 1, true},
    {"PMB", "energy blending", 1, 1, false},      {"PMB", "energy blending", 1, 2, false},
    {"LPS", "energy blending", 1, 1, false},      {"LPS", "energy blending", 1, 2, false}};
  unsigned int failures = 0;
  for (unsigned int n = 0; n < cases.size(); ++n)
    {
      const Case       &c    = cases[n];
      const std::string name = "ghost_force_free_" + std::to_string(n);
      if (root)
        std::ofstream(name + ".prm") << deck(c, name);
      MPI_Barrier(comm);
      const Result      r     = measure(c, name + ".prm", comm);
      const bool        force = c.scheme == "force blending";
      std::ostringstream what;
      what << c.material << ", " << c.scheme << ", FE_Q(" << c.degree << "), band " << c.band
           << (c.hanging ? ", hanging nodes" : "");
      const bool ok = force ? r.pd < 1e-10 && r.fe < 1e-10 && r.balance < 1e-12 :
                              std::max(r.pd, r.fe) > 1e-3 && r.balance < 1e-12;
      failures += !ok;
      if (root)
        {
          std::cout << what.str() << ": " << (ok ? "PASS" : "FAIL");
          if (!force)
            std::cout << std::setprecision(2) << " (ghost forces / E eps h^2: PD points " << r.pd << ", FE nodes "
                      << r.fe << ")";
          std::cout << std::endl;
          std::cerr << what.str() << ": PD " << r.pd << " FE " << r.fe << " balance " << r.balance << std::endl;
        }
    }
  if (root)
    std::cout << (failures == 0 ? "ALL PASSED" : "FAILED") << std::endl;
  return failures == 0 ? 0 : 1;
}
