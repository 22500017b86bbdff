#pragma once
// Loop closing before the refinement's final pass: a pose graph over the filter's trajectory. Consecutive
// poses are tied by their own relative motion (the filter's local shape), whitened by the VO control
// covariance Q_k of that frame; each detected revisit adds a relative-pose constraint between two distant
// frames. The first pose is held. A robust loss cannot tell a wrong loop at the start, where every right
// loop's residual is the whole drift, so the graph is solved with every loop, then the loop whose whitened
// residual remains farthest above a χ²₆ gate is dropped and the graph solved again from the start, until
// every remaining loop agrees with the others and the odometry. The factors are the
// motion factors of the M-step (ceres_factors_3d.hpp, paper 004 Eq. 2), so the graph is the ML problem
// without landmarks: it moves the trajectory into the basin where the final pass's E-step can associate the
// landmarks seen on both visits (digest 3.5: EM needs a start inside the gate).
#include <cstddef>
#include <vector>

#include <Eigen/StdVector>

#include "core/lie.hpp"
#include "core/types.hpp"

namespace glmbslam::backend {

/// x_i⁻¹ x_j measured at a revisit, with its whitening W (Wᵀ W = covariance⁻¹ of ξ in x_j = x_i T Exp(ξ)).
struct LoopConstraint {
  std::size_t i = 0;  ///< the earlier frame
  std::size_t j = 0;  ///< the later frame
  Pose3 relative = Pose3::Identity();
  Matrix6d W = Matrix6d::Identity();
};

struct LoopPoseGraphReport {
  int iterations = 0;  ///< of the last solve
  double initial_cost = 0.0;
  double final_cost = 0.0;
  int loops_used = 0;
  int loops_rejected = 0;  ///< inconsistent with the others and the odometry (above the gate)
};

using PoseVector = std::vector<Pose3, Eigen::aligned_allocator<Pose3>>;
using Matrix6dVector = std::vector<Matrix6d, Eigen::aligned_allocator<Matrix6d>>;

/// Optimises `poses` (x_0 held) in place. `odometry_covariance[k]` (k ≥ 1; entry 0 unused) is the covariance
/// of the motion from frame k−1 to k; it must have poses.size() entries and be positive definite.
/// `gate` bounds the squared whitened residual of a kept loop (default: χ²₆ at 0.999). Throws
/// std::invalid_argument on mismatched sizes or a constraint outside the trajectory.
LoopPoseGraphReport optimise_loop_pose_graph(PoseVector& poses, const Matrix6dVector& odometry_covariance,
                                             const std::vector<LoopConstraint>& loops, double gate = 22.46,
                                             int max_iterations = 50);

}  // namespace glmbslam::backend
