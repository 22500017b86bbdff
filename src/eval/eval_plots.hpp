#pragma once
// The PNG plots of a trajectory evaluation (LinePlot): top view, KITTI errors vs segment length, ATE along
// the path.
#include <string>
#include <vector>

#include "core/types.hpp"
#include "eval/report.hpp"

namespace glmbslam::eval {

/// Writes into `dir` (created if needed):
///   trajectory_top.png  x–z top view (KITTI camera frame: x right, z forward) of ground truth and estimate;
///   kitti_t_err.png     mean translation error (%) vs segment length;
///   kitti_r_err.png     mean rotation error (deg/100 m) vs segment length
///                       (standard lengths; the short lengths when no standard segment fits);
///   ate_error.png       position error after SE(3) and Sim(3) alignment vs distance along the ground truth.
/// Returns the paths written. Throws InputError naming the folder or file on failure.
std::vector<std::string> write_evaluation_plots(const std::string& dir, const PoseList& gt,
                                                const PoseList& est, const TrajectoryEvaluation& evaluation,
                                                const std::string& est_label = "estimate");

}  // namespace glmbslam::eval
