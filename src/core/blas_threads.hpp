#pragma once
// The thread count of the BLAS behind Ceres's sparse Cholesky (OpenBLAS when the build found it:
// CMakeLists.txt).
//
// It is a constant, not --threads: a threaded factorisation rounds differently on 1 and on 2 threads, and the
// refinement's output must be the same at any --threads (tests/backend/test_mlslam_solver.cpp). Two threads
// take the final pass on rendered 07 from 43 s (one thread) to 27 s; more gain little on these supernodes.

namespace glmbslam {

/// BLAS threads of every glmbslam process.
inline constexpr int kBlasThreads = 2;

/// Sets OpenBLAS's thread count to kBlasThreads (a no-op without OpenBLAS); main() calls it once.
void fix_blas_thread_count();

}  // namespace glmbslam
