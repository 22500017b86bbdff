#include "app/passive_openmp.hpp"

#include <cstdlib>

#include <unistd.h>

namespace glmbslam::app {

void ensure_passive_openmp(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") != nullptr) return;
  if (setenv("OMP_WAIT_POLICY", "PASSIVE", 1) != 0) return;
  execv("/proc/self/exe", argv);
  // exec failed (no /proc, say): the environment change is harmless, the run goes on with spinning workers
}

}  // namespace glmbslam::app
