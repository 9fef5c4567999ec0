#include <perideal/discretization/size_estimate.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/types.h>

#include <sc.h>

#include <cstdlib>
#include <iostream>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  // The costs (SizeCosts), measured on PMB boxes on 1 rank (set-up report's
  // memory estimate of a dry run, and the summary's "scene memory", the peak
  // minus the start-up footprint, of a one-step run):
  //   box      cells   bonds     report: bonds, points, mesh       scene memory
  //   64^3     262144  30.3e6    127.4, 41.5, 139.0 MiB            350.6 MiB
  //   50^3     125000  14.2e6     60.3, 19.9,  72.9 MiB (25^3 coarse) 176.7 MiB
  //   25^3      15625  1.65e6      7.5,  2.5,  15.1 MiB (all coarse)   37.2 MiB
  // i.e. 4.4 bytes per bond, 166 per point, 485-556 per active cell
  // (deal.II's Triangulation and DoFHandler), about 1000 per coarse cell
  // (on every rank; 2030 in all with its point, against 1610 estimated),
  // and 894 per cell and point in all at the peak (against 610 estimated).
  // The constants are below these, so that the estimate is a lower bound.

  double
  lattice_pairs(const std::array<double, 3> &n_in, const std::array<double, 3> &h_in, const double horizon)
  {
    // Bonds reach horizon * (1 + horizon_tolerance = 1e-9): a neighbour at
    // exactly 3 h counts even where 0.3 / 0.1 rounds to 2.9999999999999996.
    const double delta = horizon * (1 + 1e-10);
    // The axis with the longest reach is summed in closed form; the other
    // two are looped over, in blocks of offsets when their reach is long.
    std::array<unsigned int, 3> axis{{0, 1, 2}};
    std::array<double, 3>       reach;
    for (unsigned int d = 0; d < 3; ++d)
      reach[d] = std::min(n_in[d] - 1, std::floor(delta / h_in[d]));
    std::sort(axis.begin(), axis.end(), [&](unsigned int a, unsigned int b) { return reach[a] < reach[b]; });
    std::array<double, 3> n, h, m;
    for (unsigned int d = 0; d < 3; ++d)
      n[d] = n_in[axis[d]], h[d] = h_in[axis[d]], m[d] = reach[axis[d]];

    // Pairs along the last axis at offsets |o| <= k: n (2k+1) - k (k+1).
    const auto row = [&](const double r2) {
      if (r2 < 0)
        return 0.0;
      const double k = std::min(m[2], std::floor(std::sqrt(r2) / h[2]));
      return n[2] * (2 * k + 1) - k * (k + 1);
    };
    // Offsets 0, then blocks [a, b] of at most `stride`: every offset of a
    // block counts as its largest, b (fewer pairs: a lower bound).
    const auto blocks = [](const double reach_d) {
      std::vector<std::array<double, 2>> list{{{0, 1}}}; // offset, multiplicity
      const double stride = std::max(1.0, std::ceil(reach_d / 1000));
      for (double a = 1; a <= reach_d; a += stride)
        {
          const double b = std::min(reach_d, a + stride - 1);
          list.push_back({{b, 2 * (b - a + 1)}});
        }
      return list;
    };
    const auto bx = blocks(m[0]), by = blocks(m[1]);
    double     pairs = 0;
    for (const auto &x : bx)
      {
        const double wx = (n[0] - x[0]) * x[1], rx = delta * delta - x[0] * h[0] * x[0] * h[0];
        if (rx < 0)
          break;
        for (const auto &y : by)
          {
            const double r2 = rx - y[0] * h[1] * y[0] * h[1];
            if (r2 < 0)
              break;
            pairs += wx * (n[1] - y[0]) * y[1] * row(r2);
          }
      }
    // Without each point's pair with itself.
    return std::max(0.0, pairs - n[0] * n[1] * n[2]);
  }

  double
  max_countable_cells()
  {
    return double(std::numeric_limits<types::global_dof_index>::max()) / 3;
  }

  namespace
  {
    std::string
    num(const double x)
    {
      std::ostringstream s;
      if (x < 1e7 && x == std::floor(x))
        s << std::fixed << std::setprecision(0) << x;
      else
        s << std::setprecision(3) << x;
      return s.str();
    }

    std::string
    gib(const double bytes)
    {
      std::ostringstream s;
      s << std::setprecision(3) << bytes / (1024.0 * 1024 * 1024) << " GiB";
      return s.str();
    }
  } // namespace

  void
  report_p4est_out_of_memory()
  {
    // p4est (libsc) aborts when malloc fails; its message ("Abort: Returned
    // NULL from malloc") is printed before the handler, which must not return.
    sc_set_abort_handler([]() {
      std::cerr << "Error: p4est stopped the run (above: the reason, e.g. no memory left for the mesh): the "
                   "scene is larger than the memory of a rank, beyond its size estimate (a lower bound): use "
                   "more ranks or fewer cells"
                << std::endl;
      MPI_Abort(MPI_COMM_WORLD, 1);
      std::_Exit(1);
    });
  }

  void
  check_size(const SizeEstimate             &e,
             const AvailableMemory          &available,
             const unsigned int              ranks,
             const std::string              &what,
             const std::string              &cells_key,
             const std::string              &horizon_key,
             const bool                      print,
             const dealii::ConditionalOStream &out)
  {
    const double need       = e.bytes_per_rank(ranks);
    const double have       = available.bytes_per_rank;
    const double coarse     = e.coarse_cells * SizeCosts::coarse_cell;
    const double cell_bytes = e.cells * SizeCosts::cell + e.points * SizeCosts::point;
    const double bond_bytes = e.bonds * SizeCosts::bond;
    const bool   too_big    = need > have;
    const bool   too_many   = e.cells > max_countable_cells();
    if (!too_big && !too_many)
      return;

    const std::string estimate =
      num(e.cells) + " cells" + (e.coarse_cells > 1 ? " (" + num(e.coarse_cells) + " coarse cells on every rank)" : "") +
      ", at least " + num(e.points) + " points and " + num(e.bonds) + " bonds";
    const std::string memory = "at least " + gib(need) + " per rank on " + std::to_string(ranks) + " rank" +
                               (ranks > 1 ? "s" : "") + ", " + gib(have) + " available per rank (" +
                               available.limited_by + ")";
    if (print)
      out << "PeriDeal size estimate of " << what << " on " << ranks << " rank(s), before allocating it\n"
          << "  cells:             " << num(e.cells)
          << (e.coarse_cells > 1 ? " (coarse mesh, held by every rank: " + num(e.coarse_cells) + ")" : std::string())
          << "\n"
          << "  points:            at least " << num(e.points) << "\n"
          << "  bonds:             at least " << num(e.bonds) << " (directed)\n"
          << "  memory needed:     at least " << gib(need) << " per rank (mesh " << gib(coarse + e.cells * SizeCosts::cell / ranks)
          << ", points " << gib(e.points * SizeCosts::point / ranks) << ", bonds " << gib(bond_bytes / ranks) << ")\n"
          << "  memory available:  " << gib(have) << " per rank (" << available.limited_by << ")\n"
          << std::flush;

    // The part that dominates names the key.
    std::ostringstream message;
    // (Refinement: the finer cells also make the bonds; name the levels.)
    const bool bonds_dominate = !too_many && bond_bytes > cell_bytes && bond_bytes > coarse * ranks &&
                                cells_key.find("Refinement") == std::string::npos;
    message << (bonds_dominate ? horizon_key : cells_key) << ": " << what << " is too large"
            << (too_big ? " for the memory: " : ": ") << estimate;
    if (too_big)
      message << " need " << memory;
    if (too_many)
      message << (too_big ? "; and its " : ", ") << num(e.cells) << " cells are more than the "
              << num(std::floor(max_countable_cells()))
              << " this deal.II build can number (32-bit types::global_dof_index, 3 degrees of freedom per cell)";
    message << ". ";
    const std::string fewer =
      cells_key.find("Refinement") != std::string::npos ? "fewer refinement levels" : "fewer cells";
    if (too_many)
      message << "More ranks do not help: use " << fewer << " (" << cells_key << ")";
    else if (coarse >= have)
      message << "The coarse mesh alone takes " << gib(coarse)
              << " on every rank (p4est keeps it whole), so more ranks do not help: use fewer cells"
              << (cells_key.find("Box") != std::string::npos ?
                    " or Subdivisions with more factors of 2 (the box is a coarse mesh of Subdivisions / 2^k "
                    "cells, k <= 6, refined k times)" :
                    std::string());
    else
      {
        const double distributed = e.cells * SizeCosts::cell + e.points * SizeCosts::point + bond_bytes;
        const double more_ranks  = std::ceil(distributed / (have - coarse));
        message << "Use at least " << num(more_ranks) << " ranks with this memory each";
        if (bonds_dominate)
          message << ", a smaller horizon (" << horizon_key << ") or " << fewer << " (" << cells_key << ")";
        else
          message << ", " << fewer << " (" << cells_key << ") or a smaller horizon (" << horizon_key << ")";
      }
    AssertThrow(false, ExcMessage(message.str()));
  }
} // namespace perideal
