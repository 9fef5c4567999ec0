#include <perideal/solver/tangent.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/partitioner.h>
#include <deal.II/base/tensor.h>

#include <algorithm>
#include <cmath>

namespace perideal
{
  using namespace dealii;
  using Index = types::global_dof_index;

  void
  Tangent::reinit(const PointCloud &cloud_, const Bonds &bonds, const unsigned int hops_, const MPI_Comm comm_)
  {
    AssertThrow(hops_ == 1 || hops_ == 2, ExcMessage("the tangent couples over 1 or 2 bonds"));
    cloud = &cloud_;
    comm  = comm_;
    hops  = hops_;
    const std::vector<Index> &gid     = cloud->gid;
    const unsigned int        n_owned = cloud->n_owned();
    const unsigned int        n_local = cloud->n_local();

    owned = cloud->vector_partitioner->locally_owned_range();
    IndexSet writable(owned);
    if (hops == 2)
      writable.add_indices(cloud->vector_partitioner->ghost_indices());
    TrilinosWrappers::SparsityPattern pattern(owned, owned, writable, comm);

    std::vector<unsigned int> point_columns; // local points
    std::vector<Index>        dof_columns;
    rows.row_of.assign(n_local, numbers::invalid_unsigned_int);
    rows.start.assign(1, 0);
    rows.column.clear();
    // One point row: its block columns for the assembly buffer (ascending
    // local index) and its entries in all three DoF rows of the pattern.
    const auto add_point_row = [&](const unsigned int row) {
      std::sort(point_columns.begin(), point_columns.end());
      rows.row_of[row] = rows.start.size() - 1;
      rows.column.insert(rows.column.end(), point_columns.begin(), point_columns.end());
      rows.start.push_back(rows.column.size());
      dof_columns.clear();
      for (const unsigned int q : point_columns)
        for (unsigned int c = 0; c < dim; ++c)
          dof_columns.push_back(dim * gid[q] + c);
      std::sort(dof_columns.begin(), dof_columns.end());
      for (unsigned int r = 0; r < dim; ++r)
        pattern.add_entries(dim * gid[row] + r, dof_columns.begin(), dof_columns.end(), true);
    };

    if (hops == 1)
      for (unsigned int i = 0; i < n_owned; ++i)
        {
          point_columns.assign(1, i);
          for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
            point_columns.push_back(bonds.neighbor[b]);
          add_point_row(i);
        }
    else
      {
        // Row p collects {i} + F(i) of every owned i with p in {i} + F(i):
        // the transpose of the families (plus the diagonal) tells which i.
        std::vector<std::size_t> start(n_local + 1, 0);
        for (unsigned int i = 0; i < n_owned; ++i)
          {
            ++start[i + 1];
            for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
              ++start[bonds.neighbor[b] + 1];
          }
        for (unsigned int p = 0; p < n_local; ++p)
          start[p + 1] += start[p];
        std::vector<unsigned int> owner(start[n_local]);
        {
          std::vector<std::size_t> fill(start.begin(), start.end() - 1);
          for (unsigned int i = 0; i < n_owned; ++i)
            {
              owner[fill[i]++] = i;
              for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
                owner[fill[bonds.neighbor[b]]++] = i;
            }
        }
        std::vector<unsigned int> stamp(n_local, numbers::invalid_unsigned_int);
        for (unsigned int p = 0; p < n_local; ++p)
          {
            if (start[p] == start[p + 1])
              continue;
            point_columns.clear();
            const auto take = [&](const unsigned int q) {
              if (stamp[q] != p)
                {
                  stamp[q] = p;
                  point_columns.push_back(q);
                }
            };
            for (std::size_t k = start[p]; k < start[p + 1]; ++k)
              {
                const unsigned int i = owner[k];
                take(i);
                for (std::size_t b = bonds.offsets[i]; b < bonds.offsets[i + 1]; ++b)
                  take(bonds.neighbor[b]);
              }
            add_point_row(p);
          }
      }
    pattern.compress();
    matrix.reinit(pattern);
    rows.value.assign(9 * rows.column.size(), 0.0);
  }

  void
  Tangent::reinit_diagonal(const PointCloud &cloud_, const unsigned int hops_, const MPI_Comm comm_)
  {
    cloud = &cloud_;
    comm  = comm_;
    hops  = hops_;
    owned = cloud->vector_partitioner->locally_owned_range();
    const unsigned int n_local = cloud->n_local();
    rows.diagonal_only = true;
    rows.row_of.resize(n_local);
    rows.start.resize(n_local + 1);
    rows.column.resize(n_local);
    for (unsigned int p = 0; p < n_local; ++p)
      rows.row_of[p] = rows.start[p] = rows.column[p] = p;
    rows.start[n_local] = n_local;
    rows.value.assign(9 * n_local, 0.0);
    // The diagonal blocks of ghost rows go to their owners: 9 entries per point.
    IndexSet owned9(9 * cloud->n_global()), ghost9(9 * cloud->n_global());
    const types::global_dof_index first = cloud->n_owned() ? cloud->gid[0] : 0;
    owned9.add_range(9 * first, 9 * (first + cloud->n_owned()));
    for (unsigned int p = cloud->n_owned(); p < n_local; ++p)
      ghost9.add_range(9 * cloud->gid[p], 9 * cloud->gid[p] + 9);
    block_partitioner = std::make_shared<Utilities::MPI::Partitioner>(owned9, ghost9, comm);
  }

  void
  Tangent::finish_diagonal(const std::vector<double> &mass, std::vector<double> &inverse)
  {
    VectorType D(block_partitioner);
    for (unsigned int q = 0; q < rows.value.size(); ++q)
      D.local_element(q) = rows.value[q];
    D.compress(VectorOperation::add);
    const unsigned int n_owned = cloud->n_owned();
    inverse.resize(9 * n_owned);
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        Tensor<2, dim> block;
        for (unsigned int r = 0; r < dim; ++r)
          for (unsigned int c = 0; c < dim; ++c)
            {
              const bool fixed = constrained[dim * i + r] || constrained[dim * i + c];
              block[r][c]      = fixed ? (r == c ? 1.0 : 0.0) : D.local_element(9 * i + dim * r + c);
            }
        for (unsigned int r = 0; r < dim; ++r)
          if (!constrained[dim * i + r] && !mass.empty())
            block[r][r] += mass[dim * i + r];
        const Tensor<2, dim> inv = invert(block);
        for (unsigned int q = 0; q < 9; ++q)
          inverse[9 * i + q] = inv[q / dim][q % dim];
      }
  }

  TangentRows &
  Tangent::begin(const std::vector<std::uint8_t> &constrained_)
  {
    AssertThrow(constrained_.size() == dim * cloud->n_local(), ExcInternalError());
    constrained = constrained_;
    if (!rows.diagonal_only)
      matrix = 0;
    std::fill(rows.value.begin(), rows.value.end(), 0.0);
    rows.used = false;
    return rows;
  }

  void
  Tangent::add_to_diagonal(const std::vector<double> &values)
  {
    for (unsigned int k = 0; k < values.size(); ++k)
      if (!constrained[k])
        {
          const Index d = owned.nth_index_in_set(k);
          matrix.add(d, d, values[k]);
        }
  }

  void
  Tangent::finish(double diagonal)
  {
    // The blocks of the assembly buffer into the matrix, a DoF row at a time.
    if (rows.used)
      {
        std::vector<Index>  columns;
        std::vector<double> values;
        for (unsigned int p = 0; p < rows.row_of.size(); ++p)
          {
            const unsigned int r = rows.row_of[p];
            if (r == numbers::invalid_unsigned_int)
              continue;
            for (unsigned int d = 0; d < dim; ++d)
              {
                if (constrained[dim * p + d])
                  continue;
                columns.clear();
                values.clear();
                for (std::size_t k = rows.start[r]; k < rows.start[r + 1]; ++k)
                  for (unsigned int c = 0; c < dim; ++c)
                    if (!constrained[dim * rows.column[k] + c])
                      {
                        columns.push_back(dim * cloud->gid[rows.column[k]] + c);
                        values.push_back(rows.value[9 * k + dim * d + c]);
                      }
                matrix.add(dim * cloud->gid[p] + d, columns.size(), columns.data(), values.data(), false, false);
              }
          }
      }
    matrix.compress(VectorOperation::add);
    const unsigned int n = dim * cloud->n_owned();
    if (diagonal == 0)
      {
        double       sum  = 0;
        unsigned int free = 0;
        for (unsigned int k = 0; k < n; ++k)
          if (!constrained[k])
            {
              sum += std::abs(matrix.diag_element(owned.nth_index_in_set(k)));
              ++free;
            }
        sum      = Utilities::MPI::sum(sum, comm);
        free     = Utilities::MPI::sum(free, comm);
        diagonal = free > 0 && sum > 0 ? sum / free : 1;
      }
    for (unsigned int k = 0; k < n; ++k)
      if (constrained[k])
        {
          const Index d = owned.nth_index_in_set(k);
          matrix.set(d, d, diagonal);
        }
    matrix.compress(VectorOperation::insert);
  }

  void
  Tangent::add_finite_differences(VectorType                  &u,
                                  const VectorType            &force,
                                  const std::function<void()> &evaluate,
                                  const double                 epsilon,
                                  const double                 reach)
  {
    const std::vector<Index> &gid     = cloud->gid;
    const unsigned int        n_owned = cloud->n_owned();

    // The column points of every owned row, from the pattern.
    std::vector<std::vector<Index>> row_points(n_owned);
    IndexSet                        relevant(owned.size());
    {
      std::vector<Index> ghosts;
      for (unsigned int i = 0; i < n_owned; ++i)
        {
          auto &cols = row_points[i];
          for (auto it = matrix.begin(dim * gid[i]); it != matrix.end(dim * gid[i]); ++it)
            cols.push_back(it->column() / dim);
          std::sort(cols.begin(), cols.end());
          cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
          for (const Index g : cols)
            for (unsigned int c = 0; c < dim; ++c)
              if (!owned.is_element(dim * g + c))
                ghosts.push_back(dim * g + c);
        }
      std::sort(ghosts.begin(), ghosts.end());
      ghosts.erase(std::unique(ghosts.begin(), ghosts.end()), ghosts.end());
      relevant.add_indices(ghosts.begin(), ghosts.end());
      relevant.compress();
    }
    // Positions and constraints of every column point (2 hops may leave the
    // nonlocal ghost layer).
    const auto partitioner = std::make_shared<Utilities::MPI::Partitioner>(owned, relevant, comm);
    VectorType X(partitioner), fixed(partitioner);
    for (unsigned int k = 0; k < dim * n_owned; ++k)
      {
        X.local_element(k)     = cloud->X[k];
        fixed.local_element(k) = constrained[k];
      }
    X.update_ghost_values();
    fixed.update_ghost_values();

    std::array<double, dim> lower;
    for (unsigned int c = 0; c < dim; ++c)
      {
        double m = std::numeric_limits<double>::max();
        for (unsigned int i = 0; i < n_owned; ++i)
          m = std::min(m, cloud->X[dim * i + c]);
        lower[c] = Utilities::MPI::min(m, comm);
      }
    double side = std::numeric_limits<double>::max();
    for (unsigned int i = 0; i < n_owned; ++i)
      side = std::min(side, 0.999 * std::cbrt(cloud->volume[i]));
    side = Utilities::MPI::min(side, comm);

    // Colours: cube coordinates mod k; halve the cube until no row sees a
    // colour twice.
    unsigned int k = 0;
    const auto   colour_of = [&](const Index g) {
      std::uint64_t colour = 0;
      for (int c = dim - 1; c >= 0; --c)
        {
          const double x    = X[dim * g + c];
          const auto   cube = static_cast<std::uint64_t>(std::floor((x - lower[c]) / side));
          colour            = colour * k + cube % k;
        }
      return colour;
    };
    std::vector<std::vector<std::pair<std::uint64_t, Index>>> row_colours(n_owned);
    for (unsigned int attempt = 0;; ++attempt)
      {
        k                 = static_cast<unsigned int>(std::floor(2 * reach / side)) + 2;
        unsigned int bad  = 0;
        for (unsigned int i = 0; i < n_owned && !bad; ++i)
          {
            auto &rc = row_colours[i];
            rc.clear();
            for (const Index g : row_points[i])
              rc.emplace_back(colour_of(g), g);
            std::sort(rc.begin(), rc.end());
            for (std::size_t q = 1; q < rc.size(); ++q)
              if (rc[q].first == rc[q - 1].first)
                bad = 1;
          }
        if (Utilities::MPI::max(bad, comm) == 0)
          break;
        AssertThrow(attempt < 12, ExcMessage("finite-difference tangent: no colouring found (points closer than "
                                             "1e-3 of the cell size?)"));
        side /= 2;
      }

    const std::uint64_t n_all = std::uint64_t(k) * k * k;
    std::vector<unsigned int> present(n_all, 0);
    for (unsigned int i = 0; i < n_owned; ++i)
      present[colour_of(gid[i])] = 1;
    Utilities::MPI::max(ArrayView<const unsigned int>(present), comm, ArrayView<unsigned int>(present));
    std::vector<std::uint64_t> own_colour(n_owned);
    for (unsigned int i = 0; i < n_owned; ++i)
      own_colour[i] = colour_of(gid[i]);

    std::vector<double> original(dim * n_owned), plus(dim * n_owned);
    for (unsigned int q = 0; q < dim * n_owned; ++q)
      original[q] = u.local_element(q);
    n_colours = 0;
    for (std::uint64_t colour = 0; colour < n_all; ++colour)
      {
        if (!present[colour])
          continue;
        ++n_colours;
        for (unsigned int c = 0; c < dim; ++c)
          {
            for (const double sign : {1.0, -1.0})
              {
                for (unsigned int i = 0; i < n_owned; ++i)
                  if (own_colour[i] == colour)
                    u.local_element(dim * i + c) = original[dim * i + c] + sign * epsilon;
                u.update_ghost_values();
                evaluate();
                if (sign > 0)
                  for (unsigned int q = 0; q < dim * n_owned; ++q)
                    plus[q] = force.local_element(q);
              }
            for (unsigned int i = 0; i < n_owned; ++i)
              if (own_colour[i] == colour)
                u.local_element(dim * i + c) = original[dim * i + c];

            for (unsigned int i = 0; i < n_owned; ++i)
              {
                const auto &rc = row_colours[i];
                const auto  it = std::lower_bound(rc.begin(), rc.end(), std::make_pair(colour, Index(0)));
                if (it == rc.end() || it->first != colour)
                  continue;
                const Index column = dim * it->second + c;
                if (fixed[column] != 0)
                  continue;
                for (unsigned int r = 0; r < dim; ++r)
                  if (!constrained[dim * i + r])
                    {
                      const double df = plus[dim * i + r] - force.local_element(dim * i + r);
                      matrix.add(dim * gid[i] + r, column, -cloud->volume[i] * df / (2 * epsilon));
                    }
              }
          }
      }
    u.update_ghost_values();
    evaluate();
  }

  std::size_t
  Tangent::memory_consumption() const
  {
    return matrix.memory_consumption() + rows.value.capacity() * sizeof(double) +
           rows.column.capacity() * sizeof(unsigned int) + rows.start.capacity() * sizeof(std::size_t) +
           rows.row_of.capacity() * sizeof(unsigned int);
  }
} // namespace perideal
