#include <perideal/solver/rigid_modes.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace perideal
{
  using namespace dealii;

  namespace
  {
    // Cyclic Jacobi rotations: the eigenvalues (diagonal of a) and the
    // eigenvectors (columns of v) of a small symmetric matrix.
    template <int n>
    void
    symmetric_eigen(std::array<std::array<double, n>, n> &a, std::array<std::array<double, n>, n> &v)
    {
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
          v[i][j] = i == j;
      for (int sweep = 0; sweep < 100; ++sweep)
        {
          double off = 0, diag = 0;
          for (int i = 0; i < n; ++i)
            {
              diag += a[i][i] * a[i][i];
              for (int j = i + 1; j < n; ++j)
                off += a[i][j] * a[i][j];
            }
          if (off <= 1e-34 * diag || off == 0)
            return;
          for (int p = 0; p < n; ++p)
            for (int q = p + 1; q < n; ++q)
              {
                if (a[p][q] == 0)
                  continue;
                const double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
                const double t     = (theta >= 0 ? 1 : -1) / (std::abs(theta) + std::sqrt(theta * theta + 1));
                const double c = 1 / std::sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < n; ++k)
                  {
                    const double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                  }
                for (int k = 0; k < n; ++k)
                  {
                    const double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                  }
                for (int k = 0; k < n; ++k)
                  {
                    const double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq;
                    v[k][q] = s * vkp + c * vkq;
                  }
              }
        }
    }

    std::string
    triple(const std::array<double, 3> &a)
    {
      std::ostringstream o;
      o.precision(4);
      o << "(";
      for (unsigned int d = 0; d < 3; ++d)
        o << (d ? ", " : "") << (std::abs(a[d]) < 1e-12 ? 0.0 : a[d]);
      o << ")";
      return o.str();
    }

    // A free combination of the scaled modes (t, w extent) in words.
    std::string
    describe(const std::array<double, 6> &mode, const std::array<double, 3> &centre, const double extent)
    {
      const std::array<double, 3> t{{mode[0], mode[1], mode[2]}};
      const std::array<double, 3> w{{mode[3] / extent, mode[4] / extent, mode[5] / extent}};
      const double                ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
      const double                tt = t[0] * t[0] + t[1] * t[1] + t[2] * t[2];
      // The sign is arbitrary: make the largest component positive.
      const auto positive = [](std::array<double, 3> a) {
        const double norm = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        unsigned int big  = 0;
        for (unsigned int d = 1; d < 3; ++d)
          if (std::abs(a[d]) > std::abs(a[big]) + 1e-12 * norm)
            big = d;
        const double s = a[big] < 0 ? -1 / norm : 1 / norm;
        for (auto &x : a)
          x *= s;
        return a;
      };
      if (ww * extent * extent <= 1e-12 * tt)
        return "translation along " + triple(positive(t));
      // u = t + w x (x - c): the axis passes through c + (w x t) / |w|^2;
      // a part of t along w makes it a screw.
      const std::array<double, 3> wxt{{w[1] * t[2] - w[2] * t[1], w[2] * t[0] - w[0] * t[2], w[0] * t[1] - w[1] * t[0]}};
      const std::array<double, 3> point{{centre[0] + wxt[0] / ww, centre[1] + wxt[1] / ww, centre[2] + wxt[2] / ww}};
      const double                pitch = (t[0] * w[0] + t[1] * w[1] + t[2] * w[2]) / ww;
      return std::string(std::abs(pitch) > 1e-9 * extent ? "screw motion" : "rotation") + " about the axis through " +
             triple(point) + " along " + triple(positive(w));
    }
  } // namespace

  std::vector<std::string>
  free_rigid_modes(const std::vector<std::pair<Point<3>, unsigned int>> &prescribed,
                   const std::array<double, 3>                          &centre,
                   const double                                          extent_,
                   const MPI_Comm                                        comm,
                   std::vector<std::array<double, 6>>                   *modes)
  {
    const double extent = extent_ > 0 ? extent_ : 1.0;
    // The Gram matrix of the constraints over the modes, rotations scaled by
    // the extent so that all six are of one size; and each mode's largest
    // entry at a prescribed point.
    std::array<double, 36> gram{};
    std::array<double, 6>  largest{};
    for (const auto &[p, c] : prescribed)
      {
        std::array<double, 6> a;
        for (unsigned int m = 0; m < 6; ++m)
          a[m] = rigid_mode_value(m, c, p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]) / (m < 3 ? 1 : extent);
        for (unsigned int m = 0; m < 6; ++m)
          {
            largest[m] = std::max(largest[m], std::abs(a[m]));
            for (unsigned int l = 0; l < 6; ++l)
              gram[6 * m + l] += a[m] * a[l];
          }
      }
    Utilities::MPI::sum(ArrayView<const double>(gram.data(), 36), comm, ArrayView<double>(gram.data(), 36));
    Utilities::MPI::max(ArrayView<const double>(largest.data(), 6), comm, ArrayView<double>(largest.data(), 6));

    static const char *const name[6] = {"translation in x", "translation in y", "translation in z",
                                        "rotation about x",  "rotation about y",  "rotation about z"};
    std::vector<std::string> result;
    std::array<bool, 6>      free_coordinate{};
    for (unsigned int m = 0; m < 6; ++m)
      if (largest[m] <= 1e-9)
        {
          free_coordinate[m] = true;
          result.emplace_back(name[m]);
          if (modes)
            {
              std::array<double, 6> e{};
              e[m] = 1;
              modes->push_back(e);
            }
        }

    // Free combinations: the eigenvectors of the Gram matrix with (nearly)
    // zero eigenvalue, less what the free coordinate modes already name.
    std::array<std::array<double, 6>, 6> a, v;
    double                               scale = 0;
    for (unsigned int m = 0; m < 6; ++m)
      for (unsigned int l = 0; l < 6; ++l)
        a[m][l] = gram[6 * m + l];
    for (unsigned int m = 0; m < 6; ++m)
      scale = std::max(scale, a[m][m]);
    if (scale == 0)
      return result; // nothing prescribed: the coordinate modes say it all
    symmetric_eigen<6>(a, v);
    std::vector<std::array<double, 6>> named;
    for (unsigned int m = 0; m < 6; ++m)
      if (free_coordinate[m])
        {
          std::array<double, 6> e{};
          e[m] = 1;
          named.push_back(e);
        }
    for (unsigned int k = 0; k < 6; ++k)
      {
        if (a[k][k] > 1e-12 * scale)
          continue;
        std::array<double, 6> mode;
        for (unsigned int m = 0; m < 6; ++m)
          mode[m] = v[m][k];
        for (const auto &e : named) // Gram-Schmidt against what is named
          {
            double dot = 0;
            for (unsigned int m = 0; m < 6; ++m)
              dot += mode[m] * e[m];
            for (unsigned int m = 0; m < 6; ++m)
              mode[m] -= dot * e[m];
          }
        double norm = 0;
        for (const double x : mode)
          norm += x * x;
        norm = std::sqrt(norm);
        if (norm < 1e-3)
          continue;
        for (auto &x : mode)
          x /= norm;
        named.push_back(mode);
        result.push_back(describe(mode, centre, extent));
        if (modes)
          modes->push_back(mode);
      }
    return result;
  }
} // namespace perideal
