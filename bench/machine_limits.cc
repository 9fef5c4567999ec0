// What one core of this machine can do, for placing a bond kernel against
// it (doc/performance.md, "The machine's limits"): memory bandwidth (STREAM's
// triad), the peak of double-precision FMAs, the throughput of square roots
// and divisions, and of gathers (the bond loops' loads of their neighbours'
// data) from L1, L2, L3 and memory. Single-threaded; bench/machine_limits.sh runs
// it once alone and then as two processes at once (both cores busy).
//
// Built by the script with the project's flags for the hot loops:
//   g++ -O3 -march=native -fno-math-errno -fopenmp-simd

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <random>
#include <vector>

namespace
{
  // 8 doubles: one AVX-512 register (two AVX2 ones, which GCC splits).
  typedef double v8 __attribute__((vector_size(64)));

  double
  seconds_of(const std::chrono::steady_clock::time_point start)
  {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  /// Best of @p repeats runs of @p f, in seconds: the machine may be shared.
  template <typename F>
  double
  best_time(const int repeats, const F &f)
  {
    double best = 1e300;
    for (int r = 0; r < repeats; ++r)
      {
        const auto start = std::chrono::steady_clock::now();
        f();
        best = std::min(best, seconds_of(start));
      }
    return best;
  }

  /// Uses the chains' results, so that the compiler keeps their work, and
  /// stops if one is not finite (the timed loop then measured nothing real).
  void
  check_finite(const v8 *chains, const int n)
  {
    double sum = 0;
    for (int k = 0; k < n; ++k)
      for (int l = 0; l < 8; ++l)
        sum += chains[k][l];
    if (!std::isfinite(sum))
      std::abort();
  }

  /// STREAM triad a = b + s c over arrays far larger than the caches, in
  /// bytes per second counted as STREAM does (24 bytes per element).
  double
  triad_bandwidth()
  {
    const std::size_t   n = std::size_t(1) << 25; // 256 MiB per array
    std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
    const double        s = 3.0;
    const double        t = best_time(8, [&] {
#pragma omp simd
      for (std::size_t i = 0; i < n; ++i)
        a[i] = b[i] + s * c[i];
    });
    if (a[n / 2] != 7.0)
      std::abort();
    return 24.0 * n / t;
  }

  /// Independent FMA chains on full registers: the core's peak, in flops
  /// per second (2 per FMA and lane).
  double
  fma_peak()
  {
    constexpr int      chains = 16;
    const std::int64_t n      = 50'000'000;
    v8                 acc[chains];
    const v8           m = v8{} + 0.999999999, add = v8{} + 1e-9;
    for (int k = 0; k < chains; ++k)
      acc[k] = v8{} + k;
    const double t = best_time(3, [&] {
      for (std::int64_t i = 0; i < n; ++i)
        for (int k = 0; k < chains; ++k)
          acc[k] = acc[k] * m + add;
    });
    check_finite(acc, chains);
    return 2.0 * 8 * chains * n / t;
  }

  /// Square roots (sqrt_not_div) or divisions per second over independent
  /// lanes, as a bond loop does them.
  double
  sqrt_or_div_rate(const bool sqrt_not_div)
  {
    constexpr int      chains = 8;
    const std::int64_t n      = 20'000'000;
    v8                 x[chains];
    for (int k = 0; k < chains; ++k)
      for (int l = 0; l < 8; ++l)
        x[k][l] = 1.5 + 0.01 * (8 * k + l);
    const double t = best_time(3, [&] {
      for (std::int64_t i = 0; i < n; ++i)
        for (int k = 0; k < chains; ++k)
          {
            if (sqrt_not_div)
              for (int l = 0; l < 8; ++l)
                x[k][l] = std::sqrt(x[k][l]) + 0.75; // stays near 1.5..2.3
            else
              x[k] = 2.0 / x[k] + 0.75; // stays near 1.8..2.0
          }
    });
    check_finite(x, chains);
    return 8.0 * chains * n / t;
  }

  /// Doubles gathered per second at random indices into an array of
  /// @p bytes (the bond loop's loads of its neighbours' coordinates).
  double
  gather_rate(const std::size_t bytes)
  {
    const std::size_t          n = bytes / sizeof(double);
    const std::size_t          m = std::size_t(1) << 24;
    std::vector<double>        a(n);
    std::vector<unsigned int>  index(m);
    std::mt19937               random(12345);
    std::uniform_int_distribution<unsigned int> pick(0, n - 1);
    std::iota(a.begin(), a.end(), 0.0);
    for (auto &i : index)
      i = pick(random);
    double       sum = 0;
    const double t   = best_time(5, [&] {
      double s = 0;
#pragma omp simd reduction(+ : s)
      for (std::size_t k = 0; k < m; ++k)
        s += a[index[k]];
      sum += s;
    });
    if (!(sum > 0))
      std::abort();
    return m / t;
  }
} // namespace

int
main()
{
  std::printf("triad_bandwidth_GBps %.2f\n", triad_bandwidth() * 1e-9);
  std::printf("fma_peak_GFlops %.1f\n", fma_peak() * 1e-9);
  std::printf("sqrt_per_ns %.3f\n", sqrt_or_div_rate(true) * 1e-9);
  std::printf("div_per_ns %.3f\n", sqrt_or_div_rate(false) * 1e-9);
  std::printf("gather_L1_per_ns %.3f\n", gather_rate(std::size_t(16) << 10) * 1e-9);
  std::printf("gather_L2_per_ns %.3f\n", gather_rate(std::size_t(1) << 20) * 1e-9);
  std::printf("gather_L3_per_ns %.3f\n", gather_rate(std::size_t(16) << 20) * 1e-9);
  std::printf("gather_memory_per_ns %.3f\n", gather_rate(std::size_t(1) << 30) * 1e-9);
  return 0;
}
