#include "core/blas_threads.hpp"

#include <cstdlib>

#ifdef GLMBSLAM_HAVE_OPENBLAS
extern "C" void openblas_set_num_threads(int num_threads);  // OpenBLAS's own API (cblas.h)
#endif

namespace glmbslam {

void fix_blas_thread_count() {
#ifdef GLMBSLAM_HAVE_OPENBLAS
  if (std::getenv("OPENBLAS_NUM_THREADS") == nullptr) openblas_set_num_threads(kBlasThreads);
#endif
}

}  // namespace glmbslam
