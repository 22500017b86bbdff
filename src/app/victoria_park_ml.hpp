#pragma once
// RFS maximum-likelihood SLAM (backend/mlslam) on Victoria Park: `--algorithm mlslam` (standalone, from the
// odometry) and `--refine ml` (refinement of the filter's per-scan estimates and final map).
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "app/victoria_park_data.hpp"
#include "backend/mlslam/ml_slam_report.hpp"
#include "backend/mlslam/mlslam_config.hpp"
#include "backend/models/ackermann_motion.hpp"
#include "backend/models/victoria_park_measurement.hpp"

namespace glmbslam::app {

using VpPoseList = std::vector<Eigen::Vector3d, Eigen::aligned_allocator<Eigen::Vector3d>>;

/// Solves from x_0 = initial_pose (held; no scan) over steps 1..n (controls[k−1], measurements[k−1]).
/// standalone: `poses` and `map` are outputs (dead reckoning + births); otherwise they hold the filter's
/// estimate (one pose per step, the final map) and are refined in place. `stop` (may be empty) is asked
/// before every EM round: true ends the solve with the last round's estimate (standalone, `poses` then holds
/// the steps solved so far). Returns the solve's report (wall time, rounds, whether it was stopped).
backend::MlSlamReport solve_victoria_park_ml(const backend::AckermannMotion& motion,
                                             const backend::VictoriaParkMeasurement& model,
                                             const backend::MlSlamConfig& config,
                                             const Eigen::Vector3d& initial_pose,
                                             const std::vector<backend::AckermannMotion::Control>& controls,
                                             const std::vector<VpMeasurementSet>& measurements,
                                             bool standalone, const std::function<bool()>& stop,
                                             VpPoseList& poses, std::vector<Eigen::Vector2d>& map);

}  // namespace glmbslam::app
