#pragma once
// The thread count of the BLAS behind Ceres's sparse Cholesky (OpenBLAS when the build found it:
// CMakeLists.txt).
//
// It does not follow --threads: a threaded factorisation rounds differently on 1 and on 2 threads, and the
// refinement's output must be the same at any --threads (tests/backend/test_mlslam_solver.cpp). Two threads
// take the final pass on rendered 07 from 43 s (one thread) to 27 s on an idle 2-core machine. A threaded
// BLAS synchronises by spinning, so on a machine that is already busy (other jobs on the same cores) one
// thread is faster: OPENBLAS_NUM_THREADS, OpenBLAS's own variable, overrides the default (its value changes
// the refinement's output at round-off level, as a different BLAS would).

namespace glmbslam {

/// BLAS threads when OPENBLAS_NUM_THREADS is not set.
inline constexpr int kBlasThreads = 2;

/// Sets OpenBLAS's thread count to kBlasThreads unless OPENBLAS_NUM_THREADS is set (a no-op without
/// OpenBLAS); main() calls it once.
void fix_blas_thread_count();

}  // namespace glmbslam
