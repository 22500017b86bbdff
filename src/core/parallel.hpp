#pragma once
// Parallel loops over independent items (particles, Monte Carlo runs) with OpenMP. Results must not depend on
// the schedule: give each item its own RandomStream and write only to its own slot.
#include <cstddef>

#include <omp.h>

namespace glmbslam {

/// Number of worker threads used by parallel_for (defaults to all cores).
inline int thread_count() {
  return omp_get_max_threads();
}
/// Sets the worker thread count (≤ 0 keeps the default: all cores). The BLAS has its own, fixed count
/// (core/blas_threads.hpp).
inline void set_thread_count(int n) {
  if (n > 0) omp_set_num_threads(n);
}

/// Calls f(i) for i in [0, n) in parallel (dynamic schedule, one item at a time).
template <typename F>
void parallel_for(std::size_t n, F&& f) {
  if (n == 1) {  // one item (one particle): no team to wake
    f(std::size_t{0});
    return;
  }
  const long count = static_cast<long>(n);
#pragma omp parallel for schedule(dynamic, 1)
  for (long i = 0; i < count; ++i) f(static_cast<std::size_t>(i));
}

}  // namespace glmbslam
