#pragma once
// What one `glmbslam run` on Victoria Park produces (victoria_park_run.cpp): the filter's estimate per scan,
// its timing and final map, and with --refine ml the RFS-ML refinement (paper 004) beside it.
#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "backend/mlslam/ml_slam_report.hpp"
#include "backend/models/ackermann_motion.hpp"
#include "io/pcd_writer.hpp"

namespace glmbslam::app {

using VpStateList =
    std::vector<backend::AckermannMotion::State, Eigen::aligned_allocator<backend::AckermannMotion::State>>;

/// --refine ml: the RFS-ML refinement of the filter's estimate, kept beside it.
struct VpRefinedEstimate {
  VpStateList poses;
  std::vector<io::MapPoint> map;
  backend::MlSlamReport report;
};

struct VpRunRecord {
  VpStateList poses;
  std::vector<double> ms, ess;
  int resamples = 0;
  double total_s = 0.0;
  std::size_t steps_requested = 0;      ///< steps of the run; more than poses.size() when interrupted
  bool refinement_interrupted = false;  ///< the RFS-ML solve was stopped early (its last round's estimate)
  std::vector<io::MapPoint> map;
  std::optional<VpRefinedEstimate> refined;  ///< --refine ml
};

}  // namespace glmbslam::app
