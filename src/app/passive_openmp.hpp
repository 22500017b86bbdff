#pragma once
// OpenMP's idle workers sleep instead of spin-waiting.
//
// libgomp's default wait policy keeps each worker spinning for a while after every parallel region. The
// stereo pipeline runs its frontend and the refinement's window solves on their own threads next to the
// filter's parallel regions, so on a 2-core machine a spinning worker takes a core from them: rendered 07 (N
// = 1, refine ml, 2 threads) runs the filter at 38.8 fps with spinning and 48.3 fps with
// OMP_WAIT_POLICY=passive (N = 10: 28.6 → 31.5 fps), same output. libgomp reads OMP_WAIT_POLICY only when it
// is loaded, so the executable sets it and re-executes itself once, before anything else runs. A user's own
// OMP_WAIT_POLICY is kept as given and skips the re-execution (set one under valgrind or gdb, which would
// otherwise follow the exec).

namespace glmbslam::app {

/// When OMP_WAIT_POLICY is unset: sets it to PASSIVE and re-executes /proc/self/exe with `argv` (returns only
/// if that fails, and then the run goes on with libgomp's default).
void ensure_passive_openmp(char** argv);

}  // namespace glmbslam::app
