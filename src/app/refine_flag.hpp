#pragma once
// What `--refine ml` says where it does not apply, for every command that takes it (run on Victoria Park,
// sim).

namespace glmbslam::app {

/// --refine ml with --algorithm mlslam: the standalone solve is not refined again.
inline constexpr const char* kMlslamTakesNoRefinement =
    "--refine ml refines a filter's estimate, and --algorithm mlslam is the RFS-ML solve itself (from the "
    "odometry): leave one of them out";

}  // namespace glmbslam::app
